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

# The files whose tests read the report build (``reports.make_report.build_cached``: one build per
# process, about 15 s of CPU). Under ``--dist loadfile`` (make test) they go to one worker as one
# unit, so the session builds the report once instead of once per worker.
REPORT_BUILD_FILES = frozenset({"tests/test_report.py", "tests/test_browser.py", "tests/test_drawing.py"})


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the report-build files grouped as one unit (pytest-xdist hook)."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class ReportGroupedLoadFile(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            scope = super()._split_scope(nodeid)
            return "report-build" if scope in REPORT_BUILD_FILES else scope

    return ReportGroupedLoadFile(config, log)


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
