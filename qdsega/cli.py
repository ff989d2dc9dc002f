"""qdsega: assemble modular robots from YAML, learn their locomotion with QDSEGA in PyBullet,
and evaluate, film and report what they learnt."""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Sequence
from typing import Protocol, TextIO

from qdsega import __version__
from qdsega.commands import (
    adapt,
    assemble,
    bench,
    design,
    evaluate,
    gallery,
    match,
    plot,
    reform,
    render,
    repertoire,
    report,
    sweep,
    train,
)
from qdsega.errors import QdsegaError, QdsegaWarning

EXAMPLE = """\
a first run (a shipped formation by name, or your own YAML file):
  qdsega assemble quadruped
  qdsega train quadruped --sim memo --out runs/quad
  qdsega evaluate runs/quad && qdsega render runs/quad -o gait.mp4 && qdsega report runs/quad

every command's options: qdsega COMMAND --help; the guides: docs/ in the source."""


class ShowWarning(Protocol):
    """The signature of ``warnings.showwarning``."""

    def __call__(
        self,
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None: ...


"""The signature of ``warnings.showwarning``."""

COMMANDS = (
    assemble, train, evaluate, plot, render, report, sweep, match, bench, repertoire, adapt,
    reform, design, gallery,
)  # fmt: skip
"""Each module provides ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``."""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="qdsega",
        description=__doc__,
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"qdsega {__version__}")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        sub = subparsers.add_parser(command.NAME, help=command.HELP, description=command.HELP)
        command.add_arguments(sub)
        sub.set_defaults(handler=command.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point. Bad input exits with status 2 and one line on stderr; each
    :class:`~qdsega.errors.QdsegaWarning` is one line on stderr too."""
    args = build_parser().parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", QdsegaWarning)
            warnings.showwarning = _warning_printer(args.command, warnings.showwarning)
            return args.handler(args)
    except QdsegaError as exc:
        print(f"qdsega {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"qdsega {args.command}: interrupted", file=sys.stderr)
        return 130


def _warning_printer(command: str, others: ShowWarning) -> ShowWarning:
    """A ``warnings.showwarning`` that prints a QdsegaWarning as ``qdsega COMMAND: warning:
    ...`` and leaves any other warning to ``others``."""

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        if issubclass(category, QdsegaWarning):
            print(f"qdsega {command}: warning: {message}", file=sys.stderr)
        else:
            others(message, category, filename, lineno, file, line)

    return show


if __name__ == "__main__":
    sys.exit(main())
