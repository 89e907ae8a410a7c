# SPDX-License-Identifier: MIT
"""The Python code blocks of docs/python.md (fenced ```python) run as written
(in a scratch folder where data/ is the repository's), so the tour and the
trimesh example stay true. The Open3D block is fenced ```py: Open3D is not
installed by the tests (docs/python.md says how it was checked)."""

import os
import re

import pytest

from conftest import REPO

DOC = REPO / "docs" / "python.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(), re.S) if DOC.exists() else []


def test_docs_have_examples():
    assert len(BLOCKS) >= 2, "docs/python.md: the tour and the trimesh example"


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_doc_block_runs(tmp_path, monkeypatch, capsys, index):
    code = BLOCKS[index]
    os.symlink(REPO / "data", tmp_path / "data")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "%s block %d" % (DOC.name, index), "exec"), {"__name__": "__doc__"})
