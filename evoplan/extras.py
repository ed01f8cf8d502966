"""Optional dependencies: a feature whose library is an extra says which extra to install.

The base install runs evoplan's own algorithms, the pymoo adapters, the toolpath and zoning
problems, studies and figures. Single features need an extra (see ``pyproject.toml``):
``dask`` (the Dask backend), ``deap`` (the ``deap_easimple`` adapter), ``bbob`` (BBOB problems
through ``ioh``), ``docs`` (building the documentation), ``exchange`` (DXF and STL files of
``evoplan machine``), ``report`` (plotly for ``evoplan report``), ``cad`` (STEP and IGES
faces through OCCT), ``mesh`` (trimesh: parts given as STL, OBJ or PLY meshes,
``surface: {type: mesh}``); ``test`` installs them all.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import EvoplanError


def require(module: str, extra: str, feature: str) -> ModuleType:
    """``module`` imported, or one line naming the extra that provides it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise EvoplanError(f"{feature} needs {module.split('.')[0]!r}, which is not installed: "
                           f"pip install \"evoplan[{extra}]\"") from None
