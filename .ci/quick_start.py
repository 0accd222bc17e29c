"""Print the README's quick-start command named on the command line (``demo`` or ``tests``).

The README marks each quick-start block with an HTML comment ``<!-- quick-start: NAME ... -->`` just above its
fence; the block holds exactly one command line. CI runs that line as written, so the README and CI cannot drift.
"""

import re
import sys
from pathlib import Path


def quick_start(readme: str, name: str) -> str:
    """The one command line in the fenced block under ``<!-- quick-start: name``; SystemExit if there is none."""
    pattern = rf"<!-- quick-start: {re.escape(name)}\b[^>]*-->\s*\n```[^\n]*\n(.*?)\n```"
    found = re.findall(pattern, readme, flags=re.DOTALL)
    if len(found) != 1:
        raise SystemExit(f"README.md: expected one block marked 'quick-start: {name}', found {len(found)}")
    lines = [line for line in found[0].splitlines() if line.strip()]
    if len(lines) != 1:
        raise SystemExit(f"README.md: the block 'quick-start: {name}' must hold one command line, not {len(lines)}")
    return lines[0]


if __name__ == "__main__":
    print(quick_start((Path(__file__).parents[1] / "README.md").read_text(encoding="utf-8"), sys.argv[1]))
