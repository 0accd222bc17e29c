"""The command summary in the README and the reference in docs/cli.md are what the parser says (regenerate them
with ``python -m rig.cli.reference > docs/cli.md`` and the README block from ``usage_block()``)."""

from __future__ import annotations

from pathlib import Path

from rig.cli.reference import reference, usage_block

REPO = Path(__file__).resolve().parents[1]


def test_the_readme_command_summary_is_the_parsers_usage():
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    assert f"## Commands\n\n```\n{usage_block()}```" in readme, (
        "README's command summary differs from the parser: paste rig.cli.reference.usage_block() into it")


def test_docs_cli_is_the_parsers_help():
    assert (REPO / "docs" / "cli.md").read_text(encoding="utf-8") == reference(), (
        "docs/cli.md differs from the parser: python -m rig.cli.reference > docs/cli.md")
