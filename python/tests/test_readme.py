"""The README's Python snippet runs as printed."""
import os
import pathlib
import re
import subprocess
import sys

import detexture

SOURCE = pathlib.Path(os.environ.get("DETEXTURE_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def test_readme_python_snippet_runs(tmp_path, cube):
    """As printed, but on the small test cube in place of the 100k-point example (time)."""
    readme = (SOURCE / "README.md").read_text(encoding="utf-8")
    section = readme.split("\n## Python\n", 1)[1].split("\n## ", 1)[0]
    snippet = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "examples").mkdir()
    (tmp_path / "examples" / "textured_cube.ply").symlink_to(cube)
    r = subprocess.run([sys.executable, "-c", snippet], cwd=tmp_path, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    assert re.match(r"[1-9]\d* texture points, mean move \d", r.stdout)
    out = detexture.read_point_cloud(tmp_path / "cube.smooth.ply")
    assert len(out) == 8000 and "texture" in out.extras
