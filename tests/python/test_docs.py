"""Docs generated from native tables must match the tables."""
import os
import sys

import purlcore

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
import gen_parameters_doc  # noqa: E402


def test_parameters_doc_is_current():
    with open(os.path.join(ROOT, "docs", "parameters.md"), encoding="utf-8") as f:
        current = f.read()
    assert current == gen_parameters_doc.render_markdown(purlcore), "run: python3 tools/gen_parameters_doc.py"
