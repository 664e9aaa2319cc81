"""Argument types shared by the verbs: each error names the option and the value."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable


def finite(name: str) -> Callable[[str], float]:
    """An argparse type for a finite float; the error names the option."""

    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: not a number") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be finite")
        return v

    return conv


def positive(name: str) -> Callable[[str], float]:
    """An argparse type for a finite float > 0; the error names the option."""
    base = finite(name)

    def conv(text: str) -> float:
        v = base(text)
        if v <= 0:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be > 0")
        return v

    return conv
