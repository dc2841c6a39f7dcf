"""Shared test configuration."""
import os

from hypothesis import HealthCheck, settings

# Symbolic derivations are slow on first call; deadlines would make tests flaky.
settings.register_profile(
    "default", deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "ci", deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)
settings.load_profile("ci" if os.environ.get("CI") else "default")
