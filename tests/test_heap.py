"""The process-wide malloc tuning is opt-in for library users and applied by the CLI."""

import os
import subprocess
import sys

import pytest

SCRIPT = """
import isotween, isotween._heap as heap
bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
isotween.interpolate(bar, bar.rotate(1.0), frames=5)
print(heap._done)
"""


def run(env_value, code=SCRIPT):
    env = {k: v for k, v in os.environ.items() if k != "ISOTWEEN_KEEP_HEAP"}
    if env_value is not None:
        env["ISOTWEEN_KEEP_HEAP"] = env_value
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return out.stdout.split()[-1]


@pytest.mark.parametrize("value, applied", [(None, "False"), ("1", "True"), ("0", "False")])
def test_interpolate_tunes_malloc_only_when_asked(value, applied):
    assert run(value) == applied


def test_the_command_line_applies_it():
    code = ("import isotween._heap as heap\nfrom click.testing import CliRunner\nfrom isotween.cli import main\n"
            "CliRunner().invoke(main, ['demo', '--list'])\nprint(heap._done)")
    assert run(None, code) == "True"


@pytest.mark.skipif(not sys.platform.startswith("linux") or __import__("platform").libc_ver()[0] != "glibc",
                    reason="glibc only")
def test_glibc_is_found_by_its_soname(monkeypatch):
    import ctypes.util

    import isotween._heap as heap

    def no_search(name):  # ctypes.util.find_library runs ldconfig in a subprocess: not at every start
        raise AssertionError("searched")

    monkeypatch.setattr(ctypes.util, "find_library", no_search)
    assert callable(heap._libc().mallopt)
