"""The ``pivot-ompl`` command line: the entry point (:mod:`.main`) and one module per verb."""

from __future__ import annotations

from pivot_ompl.cli.main import main

__all__ = ["main"]
