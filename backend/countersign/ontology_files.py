"""Where the ontology files (`ontology/` at the top of the repository) are found at run time.

The files live once, at the repository top (DESIGN.md layout), and are read where they are:
`COUNTERSIGN_ONTOLOGY_DIR` if set, else `ontology/` beside the package's source tree (an
editable install or a checkout), else `ontology/` in the working directory. The Docker image
copies the folder and sets the variable. Parsed graphs are cached per process.
"""

from __future__ import annotations

import os
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    # rdflib costs ~40 ms to import; `validate` needs only the folder (for the fingerprint).
    from rdflib import Graph

MEO = "meo.ttl"
SHAPES = "shapes.ttl"
NPS_ALIGNMENT = "nps-meo3-alignment.ttl"


class OntologyNotFound(RuntimeError):
    """The ontology folder is missing: an installation problem, not a problem of the orders."""


def ontology_dir() -> Path:
    candidates: list[Path] = []
    configured = os.environ.get("COUNTERSIGN_ONTOLOGY_DIR")
    if configured:
        candidates.append(Path(configured))
    candidates.append(Path(__file__).resolve().parents[2] / "ontology")
    candidates.append(Path.cwd() / "ontology")
    for folder in candidates:
        if (folder / MEO).is_file():
            return folder
    searched = ", ".join(str(c) for c in candidates)
    raise OntologyNotFound(
        f"the MEO ontology files were not found (looked in {searched}); "
        "set COUNTERSIGN_ONTOLOGY_DIR to the folder holding meo.ttl"
    )


def ontology_path(name: str) -> Path:
    return ontology_dir() / name


@cache
def load_graph(name: str) -> Graph:
    """One ontology file, parsed once per process. Callers must not modify the result.

    Oxigraph parses the Turtle (orders/rdf_index.py), about ten times faster than rdflib's
    parser: a quarter of the MEO check of `countersign validate` went to reading these files.
    The graph holds the same statements (tests/unit/test_ontology_files.py)."""
    from rdflib import Graph

    from .orders.rdf_index import parse_turtle

    path = ontology_path(name)
    graph = Graph()
    graph.addN((s, p, o, graph) for s, p, o in parse_turtle(path.read_bytes()))
    for prefix, namespace in _prefixes(path.read_text(encoding="utf-8")):
        graph.bind(prefix, namespace, override=True)
    return graph


def _prefixes(text: str) -> list[tuple[str, str]]:
    """The document's @prefix declarations (for serialising the graph with its own names)."""
    import re

    return re.findall(r"^\s*@prefix\s+([\w-]*):\s*<([^>]*)>\s*\.", text, flags=re.MULTILINE)
