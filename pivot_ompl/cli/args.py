"""Argument types and output checks shared by the verbs: each error names the option and value."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

from pivot_ompl.errors import InputError, abridge
from pivot_ompl.fileio import check_output


def finite(name: str) -> Callable[[str], float]:
    """An argparse type for a finite float; the error names the option."""

    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: not a number") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: must be finite")
        return v

    return conv


def positive(name: str) -> Callable[[str], float]:
    """An argparse type for a finite float > 0; the error names the option."""
    base = finite(name)

    def conv(text: str) -> float:
        v = base(text)
        if v <= 0:
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: must be > 0")
        return v

    return conv


def non_negative(name: str) -> Callable[[str], float]:
    """An argparse type for a finite float >= 0; the error names the option."""
    base = finite(name)

    def conv(text: str) -> float:
        v = base(text)
        if v < 0:
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: must be >= 0")
        return v

    return conv


def time_limit(name: str = "--time") -> Callable[[str], float]:
    """An argparse type for a time limit (s): the API's one contract (``check_time_limit``).

    A number > 0; ``inf`` and anything above 1e6 s is the largest limit (1e6 s); no NaN.
    """

    def conv(text: str) -> float:
        from pivot_ompl.api import check_time_limit

        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: not a number") from None
        try:
            return check_time_limit(v, name)
        except InputError as e:
            raise argparse.ArgumentTypeError(f"{name} = {abridge(text)}: {e.reason}") from None

    return conv


def integer(name: str, minimum: int = 0, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type for an integer in ``[minimum, maximum]``; the error names the option."""

    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} = {abridge(text)}: not an integer") from None
        if v < minimum or (maximum is not None and v > maximum):
            top = "" if maximum is None else f", {maximum}"
            raise argparse.ArgumentTypeError(
                f"{name} = {abridge(text)}: must be in [{minimum}{top or ', ...'}]")
        return v

    return conv


def output_file(path: str | None, field: str, *, inputs: Iterable[str | Path | None] = (),
                suffixes: Iterable[str] = ()) -> Path | None:
    """Check an output option before any work (``None`` passes); see ``fileio.check_output``."""
    if path is None:
        return None
    return check_output(path, field=field, inputs=[i for i in inputs if i],
                        suffixes=suffixes)


def figure_file(path: str | None, field: str, *,
                inputs: Iterable[str | Path | None] = ()) -> Path | None:
    """Check a figure output: the extension must be one matplotlib writes."""
    if path is None:
        return None
    from matplotlib.backend_bases import FigureCanvasBase

    kinds = sorted(f".{k}" for k in FigureCanvasBase.get_supported_filetypes())
    return output_file(path, field, inputs=inputs, suffixes=kinds)


def output_files(inputs: Iterable[str | Path | None] = (), *,
                 figures: Iterable[str] = (), suffixes: Mapping[str, Iterable[str]] | None = None,
                 **paths: str | None) -> tuple[Path | None, ...]:
    """Check every output option of a verb before any work; the paths in the order given.

    Keyword names are the options' names with ``_`` for ``-`` (``plot=args.plot`` is
    ``--plot``); options not given are ``None``. Each is checked by :func:`output_file`
    (against ``inputs``; the options in ``figures`` must have an extension matplotlib
    writes, those in ``suffixes`` one of theirs), then all of them by
    :func:`distinct_outputs`. Write them together with ``fileio.atomic_outputs``.

    Raises:
        InputError: a bad output, or two options naming one file.
    """
    figs, kinds = set(figures), dict(suffixes or {})
    checked: dict[str, Path | None] = {}
    for name, path in paths.items():
        option = "--" + name.replace("_", "-")
        if name in figs:
            checked[name] = figure_file(path, option, inputs=inputs)
        else:
            checked[name] = output_file(path, option, inputs=inputs,
                                        suffixes=kinds.get(name, ()))
    distinct_outputs(**checked)
    return tuple(checked.values())


def distinct_outputs(**outputs: Path | None) -> None:
    """Refuse two output options naming one file (the later write would replace the other).

    Keyword names are the options' names with ``_`` for ``-`` (``plot=...`` is ``--plot``).
    """
    seen: dict[Path, str] = {}
    for name, path in outputs.items():
        if path is None:
            continue
        key = Path(os.path.abspath(path))
        option = "--" + name.replace("_", "-")
        if key in seen:
            raise InputError(option, str(path), f"is also the {seen[key]} file: give each "
                             "output its own name")
        seen[key] = option
