"""The command reference, written from the parser itself so that the documentation cannot drift from it:
``python -m rig.cli.reference`` prints docs/cli.md, and ``usage_block()`` is the README's command summary
(tests/test_cli_reference.py checks both)."""

from __future__ import annotations

import argparse
import functools

from rig.cli.main import build_parser

WIDTH = 110  # characters: the formatter's width, fixed so that the text does not depend on the terminal


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for command in action.choices.values():
        command.formatter_class = functools.partial(argparse.HelpFormatter, width=WIDTH)
    return dict(action.choices)


def usage_block() -> str:
    """One usage paragraph per command, as ``rig <command> --help`` starts."""
    lines = []
    for command in _commands().values():
        usage = command.format_usage().removeprefix("usage: ").replace(" [-h]", "").rstrip()
        lines += [line.removeprefix(" " * len("usage: ")) for line in usage.splitlines()]
    return "\n".join(lines) + "\n"


def reference() -> str:
    """docs/cli.md: every command's full help."""
    parts = ["# Command reference", "",
             "Generated from the parser (`python -m rig.cli.reference > docs/cli.md`); `rig COMMAND --help` prints "
             "the same.", ""]
    for name, command in _commands().items():
        parts += [f"## rig {name}", "", "```", command.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


if __name__ == "__main__":
    print(reference(), end="")
