"""Argument checks shared by the environments: each bad argument is a ``ValueError`` naming it."""

from __future__ import annotations

import os
from typing import Optional, Union

import numpy as np

PathLike = Union[str, "os.PathLike[str]"]

#: Largest step cap the Rust side accepts (an unsigned 32-bit integer).
MAX_STEP_CAP = 2**32 - 1


def check_render_mode(render_mode: Optional[str], modes: list) -> Optional[str]:
    """``render_mode`` must be ``None`` or one of ``modes``."""
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"render_mode: expected None or one of {modes}, got {render_mode!r}")
    return render_mode


def check_step_cap(step_cap: object) -> Optional[int]:
    """``step_cap`` must be ``None`` or an int in ``1..=2**32-1``."""
    if step_cap is None:
        return None
    if isinstance(step_cap, bool) or not isinstance(step_cap, (int, np.integer)):
        raise ValueError(f"step_cap: expected a positive int, got {step_cap!r}")
    if not 1 <= int(step_cap) <= MAX_STEP_CAP:
        raise ValueError(f"step_cap: expected an int in 1..={MAX_STEP_CAP}, got {step_cap}")
    return int(step_cap)


def text_or_file(
    text: object, text_name: str, path: Optional[PathLike], path_name: str
) -> Optional[str]:
    """The text given inline (``text``) or read from the file ``path``: not both."""
    if text is not None and path is not None:
        raise ValueError(f"{path_name}: give {text_name} or {path_name}, not both")
    if text is not None:
        if not isinstance(text, str):
            raise ValueError(f"{text_name}: expected a str, got {type(text).__name__}")
        return text
    if path is None:
        return None
    if not isinstance(path, (str, os.PathLike)):
        raise ValueError(f"{path_name}: expected a path, got {type(path).__name__}")
    try:
        with open(path, encoding="utf-8") as file:
            return file.read()
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"{path_name}: cannot read {os.fspath(path)!r}: {error}") from error


def check_str(value: object, name: str) -> Optional[str]:
    """``value`` must be ``None`` or a str."""
    if value is not None and not isinstance(value, str):
        raise ValueError(f"{name}: expected a str, got {type(value).__name__}")
    return value


def check_action(action: object) -> int:
    """An integer action (Python or numpy int, or a 0-d integer array)."""
    if isinstance(action, np.ndarray) and action.shape == () and action.dtype.kind in "iu":
        return int(action)
    if isinstance(action, bool) or not isinstance(action, (int, np.integer)):
        raise ValueError(f"action: expected an int, got {action!r}")
    return int(action)
