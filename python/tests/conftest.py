"""Shared fixtures: the `tactile` command the package is compared with, and a scratch folder."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path
from typing import List

import pytest

REPO = Path(__file__).resolve().parents[2]


class Cli:
    """The `tactile` binary: `TACTILE_BIN`, or the workspace's debug build (built if stale)."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def run(self, *args: object, ok: bool = True) -> subprocess.CompletedProcess:
        argv: List[str] = [str(self.path)] + [str(a) for a in args]
        done = subprocess.run(argv, capture_output=True, text=True)
        if ok and done.returncode != 0:
            raise AssertionError(f"{' '.join(argv)} failed:\n{done.stderr}")
        return done

    def error(self, *args: object) -> str:
        """The one-line message of a failing command, without its `tactile: error: ` prefix."""
        done = self.run(*args, ok=False)
        assert done.returncode != 0, f"tactile {args} succeeded"
        line = done.stderr.strip()
        assert "\n" not in line, line
        prefix = "tactile: error: "
        assert line.startswith(prefix), line
        return line[len(prefix):]


@pytest.fixture(scope="session")
def cli() -> Cli:
    given = os.environ.get("TACTILE_BIN")
    if given:
        return Cli(Path(given))
    subprocess.run(
        ["cargo", "build", "-q", "-p", "tactile", "--bin", "tactile", "--locked"],
        cwd=REPO,
        check=True,
    )
    return Cli(REPO / "target" / "debug" / "tactile")


@pytest.fixture(scope="session")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("tactile")
