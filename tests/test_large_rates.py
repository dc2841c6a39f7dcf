"""Rates: the SI cap every other state value has, and answers at large rates (QA 15 #2).

Reference: a uniform bar of mass m and length L on a pin at its end (tests/data/multibody/pin_bar.toml)
has theta_ddot = -3 g sin(theta) / (2 L) whatever its rate (the moment of the pin reaction about O is
zero and the centripetal acceleration of G points at O), -7.3575 rad/s**2 at 30 deg with g = 9.81.
"""
from __future__ import annotations

import json
import math

import pytest

PIN_BAR = "tests/data/multibody/pin_bar.toml"
EXACT = -1.5 * 9.81 * math.sin(math.radians(30)) / 1.0  # -7.3575 rad/s**2


def _rate_scene(tmp_path, rate: str) -> str:
    path = tmp_path / "rate.toml"
    text = open(PIN_BAR, encoding="utf-8").read().replace('rate = "1 rad/s"', f'rate = "{rate}"')
    path.write_text(text, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("rate, words", [("1e150 rad/s", "the limit is 1e+100"), ("1e-200 rad/s", "at least 1e-100")])
def test_a_rate_beyond_the_si_cap_is_refused_at_its_key(solver_cli, tmp_path, rate, words):
    """A rate of 1e150 rad/s gave theta_ddot = 0 and O_x = -2.5e299 N, and 1e160 rad/s blamed a
    singular configuration: rates now have the 1e-100 .. 1e100 SI range of every parameter and
    state value (solver.units.MAX_SI_MAGNITUDE), refused in one line naming the key, exit 2."""
    code, out, err = solver_cli("solve", _rate_scene(tmp_path, rate))
    assert (code, out, err.count("\n")) == (2, "", 1)
    assert "coordinates.theta.rate:" in err and words in err


def test_a_rate_beyond_the_si_cap_is_refused_on_the_command_line(solver_cli):
    for setting, flag in (("theta_dot=1e160 rad/s", "--set theta_dot:"), ("theta_dot=1e101 rad/s", "--set theta_dot:")):
        code, out, err = solver_cli("solve", PIN_BAR, "--set", setting)
        assert (code, out, err.count("\n")) == (2, "", 1) and flag in err and "the limit is 1e+100" in err
    code, out, err = solver_cli("solve", "data/scenes/cart_pendulum.toml", "--set", "x_dot=1e101 m/s")
    assert code == 2 and "--set x_dot:" in err and "singular" not in err
    code, out, err = solver_cli("solve", PIN_BAR, "--set", "theta_dot=1e100 rad/s", "--json")  # the cap itself: taken
    assert code == 0, err
