"""Shared fixtures: the repository, the `navkf` command line built by cargo (the same code
the package binds, so the two must agree bit for bit), and small datasets."""

import os
import pathlib
import signal
import subprocess
import sys
import textwrap

import pytest

import navkf

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The command line built by `cargo build --release -p navkf-cli` (or NAVKF_CLI)."""
    path = pathlib.Path(os.environ.get("NAVKF_CLI", ROOT / "target" / "release" / "navkf"))
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "navkf-cli"], cwd=ROOT, check=True
        )
    return path


# A 1000 s test: the paper's O-A-B-C-O path with shorter legs.
SHORT = "[trajectory]\nduration_s = 1000.0\nleg_north_m = 3000.0\nleg_east_m = 2000.0\n"


@pytest.fixture(scope="session")
def short(tmp_path_factory) -> pathlib.Path:
    """A trajectory file holding SHORT, for the command line."""
    path = tmp_path_factory.mktemp("trajectory") / "short.toml"
    path.write_text(SHORT)
    return path


@pytest.fixture(scope="session")
def pair(tmp_path_factory) -> navkf.Dataset:
    """A 1000 s test hiding an odometer scale error and a GPS latency."""
    return navkf.simulate(
        seed=7,
        trajectory=SHORT,
        effects={"odometer-scale": 0.005, "gps-latency": 0.2},
        out=tmp_path_factory.mktemp("pair") / "pair",
    )


def interrupted_at_start(setup: str, call: str) -> "tuple[int, str]":
    """Runs `setup`, then `call` in a fresh interpreter with a progress callback that prints
    `started`; sends SIGINT (Ctrl-C) at the first `started`, and returns the exit code and
    what the script printed after it (130 and `interrupted` when KeyboardInterrupt came)."""
    script = textwrap.dedent(setup) + textwrap.dedent(
        f"""
        def progress(done, total):
            print("started", flush=True)
        try:
            {call}
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(130)
        print("finished", flush=True)
        """
    )
    # Python turns SIGINT into KeyboardInterrupt only if the signal was not ignored when it
    # started, and a job started in the background (as CI may start this suite) inherits it
    # ignored: the script installs Python's default handler itself.
    prelude = "import signal, sys, navkf\nsignal.signal(signal.SIGINT, signal.default_int_handler)\n"
    p = subprocess.Popen([sys.executable, "-c", prelude + script], stdout=subprocess.PIPE, text=True)
    for line in p.stdout:
        if line.startswith("started"):
            p.send_signal(signal.SIGINT)
            break
    rest = p.stdout.read()
    return p.wait(timeout=120), rest
