"""install.sh: libraries that ldconfig lists are found (no apt-get, no warning), whatever the size of its cache."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).parents[1]


def test_install_finds_listed_libraries_without_apt(tmp_path: Path) -> None:
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    log = tmp_path / "apt.log"
    scripts = {
        # the two libraries first, then a large cache (a real one is 40 kB here, more on a desktop)
        "ldconfig": "#!/bin/sh\necho '\tlibblas.so.3 (libc6,x86-64) => /x'\necho '\tliblapack.so.3 (libc6,x86-64) => /y'\n"
                    "seq 1 200000 | sed 's/^/\tlibfiller/'\n",
        "apt-get": f"#!/bin/sh\necho \"$@\" >> {log}\n",
        "id": "#!/bin/sh\necho 0\n",
        "fakepython": "#!/bin/sh\nexit 0\n",
    }
    for name, text in scripts.items():
        (bin_ / name).write_text(text)
        (bin_ / name).chmod(0o755)
    env = dict(os.environ, PATH=f"{bin_}:{os.environ['PATH']}", PYTHON=str(bin_ / "fakepython"))
    run = subprocess.run(["bash", "scripts/install.sh"], cwd=ROOT, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert not log.exists(), "apt-get was run although ldconfig lists libblas.so.3 and liblapack.so.3"
    assert "warning" not in run.stderr
