"""The typed stubs of the compiled module match the module (they are generated, never hand-edited)."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT


def test_stubs_match_the_compiled_module():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "make_stubs.py"), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr + "\nRun `make stubs` after changing the bindings."


def test_package_is_typed():
    assert (ROOT / "python" / "vwg" / "py.typed").exists()
