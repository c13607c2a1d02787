"""The README's Python example runs as written."""

from __future__ import annotations

import re

from conftest import REPO


def test_readme_example_runs(tmp_path, monkeypatch, capsys):
    text = (REPO / "README.md").read_text()
    block = re.search(r"<!-- python-example:begin -->\s*```python\n(.*?)```\s*<!-- python-example:end -->", text, re.S)
    assert block, "README.md has no python-example block"
    code = block.group(1)
    assert len(code.strip().splitlines()) <= 12
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    mean = float(capsys.readouterr().out.split(":")[1])
    assert mean < 5.0
    assert (tmp_path / "plane.ply").is_file()
