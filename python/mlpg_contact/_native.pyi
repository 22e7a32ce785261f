"""Type stubs of the extension module (see mlpg_contact/__init__.py for the documented API)."""
from os import PathLike
from typing import Optional

import numpy as np
import numpy.typing as npt

__version__: str

class ProblemError(ValueError):
    field: Optional[str]
    value: Optional[str]
    reason: Optional[str]

class SolveError(RuntimeError):
    keys: Optional[str]

class Solved:
    def nodes(self, second: bool = False) -> npt.NDArray[np.float64]: ...
    def displacement(self, second: bool = False) -> npt.NDArray[np.float64]: ...
    def stress(self, second: bool = False) -> npt.NDArray[np.float64]: ...
    def reactions(self, second: bool = False) -> dict[str, np.ndarray]: ...
    def contact(self) -> Optional[dict[str, np.ndarray]]: ...
    def summary_json(self) -> str: ...
    def write(self, out: "str | PathLike[str]", report: bool = False) -> list[str]: ...

def solve(text: str, format: str = "toml", folder: str | None = None) -> Solved: ...
