"""Reasoning over orders with the Mission Execution Ontology (seed 000, Table 2).

    from countersign.verify.meo.reasoned import meo_reasoning
    reasoned = meo_reasoning(orders)    # the orders as RDF and what the MEO infers from them
    reasoned.explanation                # why: the inferred facts that matter, JSON-able

The pipeline, and why it is shaped this way (DESIGN.md, "MEO reasoning: measured"):

1. **Orders to RDF** (`countersign.orders.turtle.orders_to_graph`): the MEO meaning of the
   orders, with stable IRIs per mission id and element.
2. **Reasoning** (`reasoning.infer`): the graph rules G8, G9 and the chain of G10 by a search
   over the successor edges (no quadratic `follows` closure); the role rules M4, V2, V3, V4 and
   C3 by owlrl's OWL 2 RL engine over the role axioms of ontology/meo.ttl, on one representative
   per class of interchangeable goals. Tests prove the facts equal owlrl's naive full closure.
3. **Explanation** (`explain`): the inferred facts with their rule and premises, the scope of
   every constraint after C3.

The MEO rules that give findings are checked once, straight from the orders: C1, C2, M6 and M7
by `direct.meo_only_findings` (linear; the report uses it), the structural rules (M1, M2, G3, G5,
SINK, G7, G10) by `countersign.verify.structure`. The closed-world shapes of
ontology/shapes.ttl, evaluated over this reasoning natively or by pySHACL, are the oracle the
tests hold both to (tests/oracles/); `direct.RULES` gives the rules a finding cites.

A vehicle profile is reasoned about when the orders carry the profile of their target vehicle;
pass `vehicle=` to use a profile from the server's registry.

The package imports nothing itself: `validate` imports `direct` only, and rdflib and owlrl,
which `reasoned` needs, cost about a tenth of a `countersign validate` process.
"""
