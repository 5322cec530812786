"""docs/python-api.md is what tools/python_api_reference.py generates from the docstrings now."""

import subprocess
import sys

from conftest import ROOT


def test_the_api_reference_is_current():
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "python_api_reference.py"), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
