"""The ``pivot-ompl`` command line: plan, check and replay a humanoid pivoting a box, regrasping.

Exit codes for every verb: 0 success, 1 no solution (or a check that fails), 2 bad input
(the message names the field and the value), 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import atexit
import importlib
import logging
import os
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from pivot_ompl.cli.terminal import configure_logging, escaped_output
from pivot_ompl.errors import InputError, PivotError, printable

log = logging.getLogger(__name__)

EXIT_OK, EXIT_NO_SOLUTION, EXIT_BAD_INPUT = 0, 1, 2
#: Exit code after Ctrl-C (128 + SIGINT, the shells' convention): no output was replaced.
EXIT_INTERRUPTED = 130

#: Modules defining further verbs: each has ``register(subparsers)``; a missing optional
#: dependency only hides that verb.
VERB_MODULES = ("pivot_ompl.cli.steer", "pivot_ompl.cli.plan", "pivot_ompl.cli.check",
                "pivot_ompl.cli.replay", "pivot_ompl.cli.animate", "pivot_ompl.cli.bench",
                "pivot_ompl.cli.generate", "pivot_ompl.cli.bound", "pivot_ompl.cli.replan",
                "pivot_ompl.cli.import_map", "pivot_ompl.cli.simulate", "pivot_ompl.cli.robots")


#: The exit codes, as every verb's help ends.
EXIT_CODES_TEXT = ("exit codes: 0 success, 1 no solution or a check that fails, 2 bad input\n"
                   "(the message names the field and the value), 130 interrupted (Ctrl-C)")

#: A few commands per verb, shown at the end of its help.
EXAMPLES: dict[str, tuple[str, ...]] = {
    "steer": ("pivot-ompl steer --start 0 0 0 --goal 3 1 0.5 --plot steer.png",),
    "plan": ("pivot-ompl plan fig10 --out plan.json --plot plan.png",
             "pivot-ompl plan my_room.yaml --planner rrtconnect --time 10 --seed 3"),
    "check": ("pivot-ompl check plan.json", "pivot-ompl check my_room.yaml plan.json"),
    "replay": ("pivot-ompl replay plan.json --open",
               "pivot-ompl replay motion.npz --plan plan.json --html replay.html"),
    "animate": ("pivot-ompl animate plan.json --out motion.npz",),
    "check-motion": ("pivot-ompl check-motion motion.npz --plan plan.json",),
    "bench": ("pivot-ompl bench slot door --planners regrasp,rrtconnect --runs 10 --time 30 "
              "--out results/",),
    "generate": ("pivot-ompl generate --family walls --walls 2 --seed 1 --out my_scenes",),
    "bound": ("pivot-ompl bound fig10",),
    "import-map": ("pivot-ompl import-map my_floor.yaml --out floor.yaml --start 1 2 0 "
                   "--goal 8 3 1.57 --clean specks",),
    "robots": ("pivot-ompl robots", "pivot-ompl robots --json"),
    "replan": ("pivot-ompl replan slot plan.json --box 3.0 1.6 0.1 --out new.json "
               "--scene-out new.yaml",),
    "simulate": ("pivot-ompl simulate plan.json --motion motion.npz --out report.json",
                 "pivot-ompl simulate plan.json --motion motion.npz --out report.json "
                 "--perturb slip --replan --seed 3"),
}


def plain(doc: str) -> str:
    """A docstring as help text: reST roles and ``literal`` markup removed."""
    doc = re.sub(r":[a-z]+:`~?([^`]*)`", lambda m: m.group(1).rsplit(".", 1)[-1], doc)
    return doc.replace("``", "").strip()


class _HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions kept as written; each option's default shown unless its help says it."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        default = action.default
        if ("default" in text or default is None or default is False or default is True
                or default == argparse.SUPPRESS
                or (isinstance(default, list | tuple) and not default)
                or (not action.option_strings and action.nargs not in ("?", "*"))):
            return text
        return f"{text} (default: %(default)s)"


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors exit with code 2 and name the argument."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:  # noqa: D102
        self.print_usage(sys.stderr)
        if len(message) > 300:  # argparse echoes whole values: keep the message short
            message = message[:297] + "..."
        print(f"{self.prog}: error: {printable(message)}", file=sys.stderr)
        raise SystemExit(EXIT_BAD_INPUT)


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every available verb."""
    parser = _Parser(prog="pivot-ompl", description=plain(__doc__.split("\n\n")[0]),
                     epilog="examples:\n  pivot-ompl plan fig10 --out plan.json --plot "
                            "plan.png\n  pivot-ompl replay plan.json --open\n  pivot-ompl "
                            "<verb> --help\n\n" + EXIT_CODES_TEXT)
    parser.add_argument("--log-level", default="INFO",
                        choices=["DEBUG", "INFO", "WARNING", "ERROR"],
                        help="logging level; DEBUG also shows OMPL's own log")
    sub = parser.add_subparsers(dest="verb", required=True, parser_class=_Parser)
    for name in VERB_MODULES:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as e:
            if e.name and (e.name == name or name.startswith(e.name + ".")):
                continue  # that verb is not part of this build
            raise
        before = set(sub.choices)
        mod.register(sub)
        for verb in set(sub.choices) - before:
            _explain(sub.choices[verb], verb, mod.__doc__ or "")
    return parser


def _explain(p: argparse.ArgumentParser, verb: str, doc: str) -> None:
    """A verb's help: its module's docstring as the description, examples and exit codes."""
    first = doc.strip().splitlines()[0] if doc.strip() else ""
    if p.description in (None, first):
        p.description = plain(doc) or None
    else:
        p.description = plain(p.description)
    examples = "".join(f"\n  {e}" for e in EXAMPLES.get(verb, ()))
    p.epilog = (f"examples:{examples}\n\n" if examples else "") + EXIT_CODES_TEXT


def _quiet_exit() -> None:
    """At exit, send fd 2 to /dev/null.

    nanobind lists 'leaked instances' of OMPL objects that Python keeps until the very end
    (harmless; tracebacks and exit codes are kept).
    """
    sys.stderr.flush()
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 2)


def _ompl_log_level(level: str) -> None:
    from ompl import util as ou

    ou.setLogLevel({"DEBUG": ou.LogLevel.LOG_DEBUG, "INFO": ou.LogLevel.LOG_WARN,
                    "WARNING": ou.LogLevel.LOG_WARN, "ERROR": ou.LogLevel.LOG_ERROR}[level])


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the exit code.

    Ctrl-C at any moment (imports included) prints one line and returns
    :data:`EXIT_INTERRUPTED`: outputs are written atomically, so nothing half-written is left
    and no existing file was replaced.
    """
    try:
        return _run(argv)
    except KeyboardInterrupt:
        verb = _verb_of(sys.argv[1:] if argv is None else argv)
        print(f"pivot-ompl{' ' + verb if verb else ''}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _verb_of(argv: Sequence[str]) -> str:
    """The verb of a command line, or ``""`` (for a message when parsing did not end)."""
    words = [str(a) for a in argv]
    for i, word in enumerate(words):
        if not word.startswith("-") and not (i and words[i - 1] == "--log-level"):
            return word
    return ""


def _run(argv: Sequence[str] | None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # usage error (2) or --help (0): a code, also for in-process callers
        return e.code if isinstance(e.code, int) else EXIT_BAD_INPUT
    configure_logging(getattr(logging, args.log_level))
    logging.getLogger("matplotlib").setLevel(logging.WARNING)
    _ompl_log_level(args.log_level)
    if argv is None:  # a real process, not a test calling main()
        atexit.register(_quiet_exit)
    with escaped_output():
        return _verb(args)


def _verb(args: argparse.Namespace) -> int:
    """Run the parsed verb; its errors as exit codes."""
    try:
        return int(args.func(args))
    except InputError as e:
        print(f"pivot-ompl {args.verb}: error: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except PivotError as e:
        print(f"pivot-ompl {args.verb}: {e}", file=sys.stderr)
        return EXIT_NO_SOLUTION
    except OSError as e:  # an output that cannot be written (permissions, full disk)
        print(f"pivot-ompl {args.verb}: error: {e.filename or ''}: {e.strerror or e}",
              file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
