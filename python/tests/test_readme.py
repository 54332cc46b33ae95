"""The Python examples of README.md and python/README.md run and arrive."""

import re

import numpy as np
import pytest

from conftest import REPO


@pytest.mark.parametrize("readme", ["README.md", "python/README.md"])
def test_the_readme_example_arrives(readme):
    text = (REPO / readme).read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1, f"{readme}: {len(blocks)} python blocks"
    scope = {}
    exec(compile(blocks[0], readme, "exec"), scope)
    assert np.linalg.norm(scope["x"] - scope["nav"].goal) <= 0.01
    assert scope["nav"].obstacle_count >= 1
