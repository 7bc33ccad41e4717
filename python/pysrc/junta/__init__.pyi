"""Type stubs of the ``junta`` package (see ``__init__.py`` for the
documentation of each name)."""

import builtins
import enum
from os import PathLike
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._errors import (
    FileError as FileError,
    FileNotFound as FileNotFound,
    InputError as InputError,
    JuntaError as JuntaError,
    LawError as LawError,
    TangentError as TangentError,
)

__version__: str

_Path = Union[str, "PathLike[str]"]
_F64 = NDArray[np.float64]

class Status(str, enum.Enum):
    COMPLETED = "completed"
    STOPPED = "stopped"
    FAILED = "failed"
    INTERRUPTED = "interrupted"
    @classmethod
    def from_status_line(cls, line: str) -> Status: ...

class Flow(enum.Enum):
    CONTINUE = "continue"
    STOP = "stop"

class Stop:
    reason: str
    def __init__(self, reason: str = ...) -> None: ...

#: What a run's callback may return.
CallbackAnswer = Union[None, Flow, Stop]

class Law:
    state_len: int
    initial_stiffness: tuple[float, float, float]
    tangent_kind: str
    output_names: Sequence[str]
    fracture_properties: Optional[Mapping[str, float]]
    warnings: Sequence[str]
    def evaluate(
        self, jump: _F64, state: _F64, step: dict[str, Any]
    ) -> tuple[ArrayLike, ArrayLike, ArrayLike]: ...

class Mesh:
    nodes: _F64
    cells: builtins.list[dict[str, Any]]
    def __init__(self, d: Mapping[str, Any]) -> None: ...

class Frame:
    increment: int
    load_factor: float
    displacement: _F64
    solid_stress: _F64
    solid_strain: _F64
    solid_material_stress: _F64
    solid_position: _F64
    solid_block: NDArray[np.int64]
    solid_element: NDArray[np.int64]
    interface_traction: _F64
    interface_jump: _F64
    interface_position: _F64
    interface_block: NDArray[np.int64]
    interface_element: NDArray[np.int64]
    interface_outputs: dict[str, _F64]
    mesh: Optional[Mesh]
    def __init__(self, d: Mapping[str, Any], mesh: Optional[Mesh] = None) -> None: ...
    def to_meshio(self) -> Any: ...
    def to_pyvista(self) -> Any: ...

class Results:
    status: Status
    status_line: str
    curve: dict[str, Any]
    summary: dict[str, Any]
    frames: builtins.list[Frame]
    frame: Optional[Frame]
    mesh: Mesh
    output: Optional[str]
    failure: Optional[str]
    notes: builtins.list[str]
    warnings: builtins.list[str]
    def __init__(self, d: Mapping[str, Any]) -> None: ...

class Simulation:
    def __init__(self, native: Any) -> None: ...
    @classmethod
    def from_file(
        cls,
        path: _Path,
        overrides: Optional[Union[Mapping[str, Any], Sequence[tuple[str, Any]]]] = None,
        solver: Optional[Union[str, Mapping[str, Any], Sequence[str]]] = None,
    ) -> Simulation: ...
    @classmethod
    def from_text(cls, text: str, path: _Path = ...) -> Simulation: ...
    @property
    def input(self) -> str: ...
    @property
    def is_incremental(self) -> bool: ...
    @property
    def notes(self) -> builtins.list[str]: ...
    @property
    def mesh(self) -> Mesh: ...
    def check(self) -> dict[str, Any]: ...
    def run(
        self,
        callback: Optional[Callable[[dict[str, Any]], CallbackAnswer]] = None,
        output: Optional[_Path] = None,
        max_increments: Optional[int] = None,
        frames_every: Optional[int] = None,
    ) -> Results: ...

def catalog() -> builtins.list[dict[str, Any]]: ...
def list() -> builtins.list[dict[str, Any]]: ...
def register_law(
    name: str,
    factory: Callable[[dict[str, Any]], Any],
    description: Optional[str] = None,
    params: Optional[Union[Mapping[str, str], Sequence[tuple[str, str]]]] = None,
) -> None: ...
def unregister_law(name: str) -> bool: ...
def evaluate_law(
    law: Any,
    jumps: ArrayLike,
    state: Optional[ArrayLike] = None,
    step: Optional[Mapping[str, Any]] = None,
) -> tuple[_F64, _F64, _F64]: ...
def check_tangent(
    law: Any,
    jumps: ArrayLike,
    state: Optional[ArrayLike] = None,
    step: Optional[Mapping[str, Any]] = None,
    h: float = 1e-7,
    rtol: float = 1e-5,
    raise_on_error: bool = False,
) -> dict[str, Any]: ...
