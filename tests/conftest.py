"""Shared test configuration."""
import os

import pytest

from hypothesis import HealthCheck, settings

# Symbolic derivations are slow on first call; deadlines would make tests flaky.
settings.register_profile(
    "default", deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "ci", deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)
settings.load_profile("ci" if os.environ.get("CI") else "default")


@pytest.fixture
def solver_cli(capsys):
    """Run ``python -m solver ARGV...`` in process: returns (exit code, stdout, stderr)."""
    from solver.__main__ import main

    def run(*argv: str) -> tuple[int, str, str]:
        with pytest.raises(SystemExit) as exc:
            raise SystemExit(main(list(argv)))
        out = capsys.readouterr()
        return exc.value.code, out.out, out.err

    return run


@pytest.fixture
def analysis_cli(capsys):
    """Run ``python -m analysis ARGV...`` in process: returns (exit code, stdout, stderr)."""
    from analysis.__main__ import main

    def run(*argv: str) -> tuple[int, str, str]:
        code = main(list(argv))
        out = capsys.readouterr()
        return code, out.out, out.err

    return run
