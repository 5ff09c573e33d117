"""Argument checks shared by the package, as Python's own functions check theirs: a value of
the wrong type is a ``TypeError``, a value of the right type but out of range a ``ValueError``,
a file that is not there a ``FileNotFoundError``; each message starts with the argument's name.
"""

from __future__ import annotations

import os
from typing import Optional, Sequence, Union

import gymnasium
import numpy as np

#: A path as the package takes it: a ``str`` or an ``os.PathLike`` (e.g. ``pathlib.Path``).
PathLike = Union[str, "os.PathLike[str]"]

#: Largest step cap the Rust side accepts (an unsigned 32-bit integer).
MAX_STEP_CAP = 2**32 - 1


def type_name(value: object) -> str:
    """The name of ``value``'s type, for messages."""
    return type(value).__name__


def is_int(value: object) -> bool:
    """Whether ``value`` is an integer (Python or numpy), not a bool."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def check_int(
    value: object, name: str, *, minimum: int = 0, maximum: Optional[int] = None
) -> int:
    """``value`` as an int in ``minimum..=maximum``: ``TypeError`` if it is not an integer,
    ``ValueError`` if it is out of range."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}: expected an int, got {type_name(value)} {value!r}")
    number = int(value)
    if number < minimum or (maximum is not None and number > maximum):
        upper = "" if maximum is None else f"..={maximum}"
        raise ValueError(f"{name}: expected an int in {minimum}{upper}, got {number}")
    return number


def check_bool(value: object, name: str) -> bool:
    """``value`` must be a bool (``TypeError`` otherwise)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected True or False, got {type_name(value)} {value!r}")
    return bool(value)


def check_render_mode(render_mode: object, modes: Sequence[str]) -> Optional[str]:
    """``render_mode`` must be ``None`` or one of ``modes``."""
    if render_mode is None:
        return None
    if not isinstance(render_mode, str):
        raise TypeError(f"render_mode: expected None or a str, got {type_name(render_mode)}")
    if render_mode not in modes:
        raise ValueError(f"render_mode: expected None or one of {list(modes)}, got {render_mode!r}")
    return render_mode


def check_step_cap(step_cap: object) -> Optional[int]:
    """``step_cap`` must be ``None`` or an int in ``1..=2**32-1``."""
    if step_cap is None:
        return None
    return check_int(step_cap, "step_cap", minimum=1, maximum=MAX_STEP_CAP)


def check_path(path: object, name: str) -> str:
    """``path`` (a ``str`` or ``os.PathLike``) as a ``str``; ``TypeError`` otherwise."""
    if isinstance(path, str):
        return path
    if isinstance(path, os.PathLike):
        text = os.fspath(path)
        if isinstance(text, str):
            return text
    raise TypeError(f"{name}: expected a path (str or os.PathLike), got {type_name(path)}")


def read_text(path: object, name: str) -> str:
    """The text of the file ``path``: ``FileNotFoundError`` if it is not there, ``ValueError``
    if it cannot be read as UTF-8 text."""
    file = check_path(path, name)
    try:
        with open(file, encoding="utf-8") as handle:
            return handle.read()
    except FileNotFoundError as error:
        raise FileNotFoundError(f"{name}: no file {file!r}") from error
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"{name}: cannot read {file!r}: {error}") from error


def text_or_file(
    text: object, text_name: str, path: object, path_name: str
) -> Optional[str]:
    """The text given inline (``text``) or read from the file ``path``: not both."""
    if text is not None and path is not None:
        raise ValueError(f"{path_name}: give {text_name} or {path_name}, not both")
    if text is not None:
        if not isinstance(text, str):
            raise TypeError(f"{text_name}: expected a str, got {type_name(text)}")
        return text
    if path is None:
        return None
    return read_text(path, path_name)


def check_str(value: object, name: str) -> Optional[str]:
    """``value`` must be ``None`` or a str."""
    if value is not None and not isinstance(value, str):
        raise TypeError(f"{name}: expected a str, got {type_name(value)}")
    return value


def require_str(value: object, name: str) -> str:
    """``value`` must be a str."""
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected a str, got {type_name(value)}")
    return value


def discrete(n: int) -> "gymnasium.spaces.Space[int]":
    """``Discrete(n)``: a space of numpy ``int64`` values, which hold the ints the
    environments take and return (typed as such for ``gymnasium.Env[int, int]``)."""
    return gymnasium.spaces.Discrete(n)  # type: ignore[return-value]


def check_action(action: object) -> int:
    """An integer action (Python or numpy int, or a 0-d integer array); ``TypeError`` for
    anything else (a float, even ``1.0``, is not an action)."""
    if isinstance(action, np.ndarray) and action.shape == () and action.dtype.kind in "iu":
        return int(action)
    if isinstance(action, (bool, np.bool_)) or not isinstance(action, (int, np.integer)):
        raise TypeError(f"action: expected an int, got {type_name(action)} {action!r}")
    return int(action)


def check_actions(actions: object, num_envs: int) -> "np.ndarray[tuple[int], np.dtype[np.int64]]":
    """A vector env's actions: integers (a list of ints or an integer array) of shape
    ``(num_envs,)``, as a C-contiguous ``int64`` array; ``TypeError`` for floats, bools or
    text, exactly as the single env refuses them."""
    array = np.asarray(actions)
    if array.dtype.kind not in "iu":
        raise TypeError(
            f"actions: expected integers, got an array of dtype {array.dtype} ({actions!r})"
        )
    if array.shape != (num_envs,):
        raise ValueError(f"actions: expected shape ({num_envs},), got {array.shape}")
    if array.dtype.kind == "u" and array.size and int(array.max()) >= 2**63:
        raise ValueError(f"actions: {int(array.max())} is not an action")
    return np.ascontiguousarray(array, dtype=np.int64)
