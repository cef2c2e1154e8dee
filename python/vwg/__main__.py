"""``python -m vwg``: the ``vwg`` command; ``python -m vwg --cmake-dir`` (or ``--include-dir``) prints where
the installed C++ SDK is (vwg.sdk)."""

from __future__ import annotations

import sys

from vwg.cli import main
from vwg.errors import Error
from vwg.sdk import get_cmake_dir, get_include


def run(argv: list[str]) -> int:
    where = {"--cmake-dir": get_cmake_dir, "--include-dir": get_include}
    if len(argv) == 1 and argv[0] in where:
        try:
            print(where[argv[0]]())
        except Error as e:
            print(f"vwg: error: {e}", file=sys.stderr)
            return 2
        return 0
    return main(argv)


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
