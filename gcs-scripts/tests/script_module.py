"""The scripts beside the package (``gcs-scripts/*.py``) imported as modules by their tests."""
from __future__ import annotations

import importlib.util
import pathlib
import sys
from types import ModuleType

#: The folder holding the scripts.
SCRIPTS_DIR = pathlib.Path(__file__).resolve().parents[1]


def load_script(name: str) -> ModuleType:
    """``gcs-scripts/NAME.py`` as a module (a script, not part of the package); the scripts' folder
    is on ``sys.path`` as when a script runs, so a script may import its siblings."""
    if str(SCRIPTS_DIR) not in sys.path:
        sys.path.append(str(SCRIPTS_DIR))
    path = SCRIPTS_DIR / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
