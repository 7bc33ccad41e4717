"""Type stubs of the native module ``junta._junta`` (PyO3). Users import
``junta``; these are the functions and the class its Python layer calls."""

from os import PathLike
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
from numpy.typing import NDArray

__version__: str
debug_build: bool

_Path = Union[str, "PathLike[str]"]
_Step = Mapping[str, Any]
_LawArrays = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]

class Simulation:
    @staticmethod
    def from_file(
        path: _Path,
        overrides: Optional[Union[Mapping[str, Any], Sequence[tuple[str, Any]]]] = None,
        solver: Optional[Union[str, Mapping[str, Any], Sequence[str]]] = None,
    ) -> Simulation: ...
    @staticmethod
    def from_text(text: str, path: _Path = ...) -> Simulation: ...
    @property
    def input(self) -> str: ...
    @property
    def ready(self) -> bool: ...
    @property
    def is_incremental(self) -> bool: ...
    @property
    def notes(self) -> list[str]: ...
    def mesh(self) -> dict[str, Any]: ...
    def check(self) -> dict[str, Any]: ...
    def run(
        self,
        callback: Optional[Callable[[dict[str, Any]], Optional[str]]] = None,
        output: Optional[_Path] = None,
        max_increments: Optional[int] = None,
        frames_every: Optional[int] = None,
    ) -> dict[str, Any]: ...

def catalog() -> list[dict[str, Any]]: ...
def list_text() -> str: ...
def register_law(
    name: str,
    factory: Callable[[dict[str, Any]], Any],
    description: Optional[str] = None,
    params: Optional[Sequence[tuple[str, str]]] = None,
) -> None: ...
def unregister_law(name: str) -> bool: ...
def evaluate_law(
    law: Any,
    jump: Sequence[tuple[float, float, float]],
    state: Sequence[float],
    step: Optional[_Step] = None,
) -> _LawArrays: ...
def evaluate_registered(
    key: str,
    params: Mapping[str, Any],
    jump: Sequence[tuple[float, float, float]],
    state: Optional[Sequence[float]] = None,
    step: Optional[_Step] = None,
) -> _LawArrays: ...
