"""Where the ontology files (`ontology/` at the top of the repository) are found at run time.

The files live once, at the repository top (DESIGN.md layout), and are read where they are:
`COUNTERSIGN_ONTOLOGY_DIR` if set, else `ontology/` beside the package's source tree (an
editable install or a checkout), else `ontology/` in the working directory. The Docker image
copies the folder and sets the variable. The files are parsed by `orders.ontology.load_graph`
(this module imports nothing heavy: the settings, and pydantic with them, only when
the folder is looked up).
"""

from __future__ import annotations

from pathlib import Path

MEO = "meo.ttl"
NPS_ALIGNMENT = "nps-meo3-alignment.ttl"


class OntologyNotFound(RuntimeError):
    """The ontology folder is missing: an installation problem, not a problem of the orders."""


def ontology_dir() -> Path:
    from .settings import InstallationEnvironment, read

    candidates: list[Path] = []
    configured = read(InstallationEnvironment).ontology_dir
    if configured is not None:
        candidates.append(configured)
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
