"""The expression language of mission orders (DESIGN.md, Orders format): its syntax.

    depth_m >= 20 or lane_distance_m >= 1000
    not (behavior == 'surface' and context('shipping_lane'))
    battery_reserve_pct >= 20 implies speed_mps <= 2.5

Numbers, quoted strings, `true`/`false`, quantity names, `behavior`, `area`, `context('tag')`,
`+ - * /`, comparisons (`== != < <= > >=`, chains such as `3 <= altitude_m <= 12`), `not`,
`and`, `or` and `implies` (weakest, right-associative). Nothing is ever evaluated by Python's
`eval`: text becomes tokens (lexer), tokens become a small immutable tree (parser, tree), and
`verify.expressions` checks the tree against the quantities the orders declare (plus the
built-in maritime vocabulary here), folds it and translates it for z3.

Every error carries the 1-based column where it was found, so a finding can say
"C4, column 19: expected a value after '>='". Pathological input is bounded before it costs
anything: the text length, the nesting depth, the number of terms and the size of each number
are limited, and the tree is flat for long chains of `and`, `or`, `+` and `*`, so that no
later recursion goes deeper than the nesting the author wrote.

Every interpreter of the tree (words, reads, and in `verify`, `rehearse` and `export` the type
checker, partial evaluation, SMT, monitors, helm conditions) is an `ExprVisitor` (visit.py), so
mypy rejects a node kind that one of them leaves out.

The syntax lives under `orders` so that the orders' own readers and writers (Turtle, plain
text) read expressions with the one parser; it imports nothing outside `orders`.
"""

from .errors import (
    MAX_DEPTH,
    MAX_DIGITS,
    MAX_EXPONENT,
    MAX_LENGTH,
    MAX_TERMS,
    MAX_TOKENS,
    ExprError,
)
from .lexer import RESERVED, Token, tokenize
from .parser import first_col, parse
from .reads import Reads, expression_quantities, identifiers, reads, walk
from .tree import (
    Compare,
    Context,
    Expr,
    Implies,
    Logic,
    Name,
    Neg,
    Not,
    Num,
    Product,
    Special,
    Sum,
    Text,
    Truth,
)
from .visit import ExprVisitor, children
from .vocabulary import MARITIME_QUANTITIES, quantity_table
from .words import (
    describe,
    in_tag,
    number_words,
    quantity_words,
    tag_state,
    tag_words,
    with_article,
    with_unit,
)

__all__ = [
    "MARITIME_QUANTITIES", "MAX_DEPTH", "MAX_DIGITS", "MAX_EXPONENT", "MAX_LENGTH", "MAX_TERMS",
    "MAX_TOKENS", "RESERVED", "Compare", "Context", "Expr", "ExprError", "ExprVisitor", "Implies",
    "Logic", "Name", "Neg", "Not", "Num", "Product", "Reads", "Special", "Sum", "Text", "Token",
    "Truth", "children", "describe", "expression_quantities", "first_col", "identifiers",
    "in_tag", "number_words", "parse", "quantity_table", "quantity_words", "reads", "tag_state",
    "tag_words", "tokenize", "walk", "with_article", "with_unit",
]
