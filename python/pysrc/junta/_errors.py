"""The exceptions of the ``junta`` package (one mapping from the run API's
error type, made by the native module ``junta._junta``).

================================  =============================================
``junta.Error`` (Rust)             Python exception
================================  =============================================
the input (a key, a line, TOML)    ``InputError`` (also a ``ValueError``)
a file that does not exist         ``FileNotFound`` (also ``FileNotFoundError``)
another file error                 ``FileError`` (also an ``OSError``)
a Python law returned garbage      ``LawError``
anything else, or a bug            ``JuntaError``
================================  =============================================

Every message is the one the command line prints after ``error:``. A run
that fails (an increment below the smallest size) is *not* an exception:
``Results.status == "failed"`` and ``Results.failure`` holds the message.
"""

__all__ = [
    "JuntaError",
    "InputError",
    "FileError",
    "FileNotFound",
    "LawError",
    "TangentError",
]


class JuntaError(Exception):
    """Base class of Junta's errors."""


class InputError(JuntaError, ValueError):
    """The input (scene, deck, mesh, override, law parameters) is not valid:
    the message names the file and the key or line, and what would be valid."""


class FileError(JuntaError, OSError):
    """A file could not be read or written."""


class FileNotFound(FileError, FileNotFoundError):
    """A file does not exist."""


class LawError(JuntaError):
    """A traction law written in Python returned an array of the wrong
    shape or with non-finite values (the message names the law, the array,
    and the expected and returned shapes). An exception the law raises is
    re-raised as itself instead."""


class TangentError(JuntaError):
    """``check_tangent(..., raise_on_error=True)``: a law's tangent differs
    from the central differences of its traction."""
