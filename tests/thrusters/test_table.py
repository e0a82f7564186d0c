"""Datasheet (lookup-table) thruster: the bundled T200 table, interpolation, lag, inverse and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.errors import UvmsInputError
from uvms.thrusters.table import (STANDARD_GRAVITY, TableThrusterParameters, load_thruster_table, t200_table,
                                  table_command, table_exact, table_rk4_step, table_thrust)

KGF = 9.80665


@pytest.fixture(scope="module")
def t200():
    return t200_table(time_constant=0.05)


def test_t200_table_carries_the_published_16v_numbers(t200):
    """Blue Robotics' 16 V sheet: 201 points every 4 us from 1100 to 1900 us; -4.07 kgf at 1100 us,
    5.25 kgf at 1900 us, 0 from 1472 to 1528 us, 0.87 kgf at 1624 us, -1.35 kgf at 1308 us (2-decimal
    values as quoted from the sheet)."""
    assert STANDARD_GRAVITY == KGF
    np.testing.assert_array_equal(t200.command, np.arange(1100.0, 1901.0, 4.0))
    published = {1100: -4.07, 1308: -1.35, 1472: 0.0, 1500: 0.0, 1528: 0.0, 1624: 0.87, 1840: 4.25, 1900: 5.25}
    for pwm, kgf in published.items():
        i = int((pwm - 1100) // 4)
        assert t200.thrust[i] / KGF == pytest.approx(kgf, abs=0.005)
    assert t200.voltage == 16.0 and "T200" in t200.source
    assert t200.max_thrust == pytest.approx(5.24503549333333 * KGF, rel=1e-14)
    assert t200.min_thrust == pytest.approx(-4.06947622666667 * KGF, rel=1e-14)


def test_interpolation_is_exact_at_table_points_and_linear_between(t200):
    p = t200.as_array()
    for c, T in zip(t200.command, t200.thrust):
        assert table_thrust(p, c) == T
    for i in range(t200.command.size - 1):
        mid = 0.5 * (t200.command[i] + t200.command[i + 1])
        assert table_thrust(p, mid) == pytest.approx(0.5 * (t200.thrust[i] + t200.thrust[i + 1]), rel=1e-14,
                                                     abs=1e-14)
    assert table_thrust(p, 900.0) == t200.thrust[0]          # clipped outside the table
    assert table_thrust(p, 2100.0) == t200.thrust[-1]


def test_thrust_is_monotonic_in_the_command(t200, rng):
    p = t200.as_array()
    commands = np.sort(rng.uniform(1000, 2000, 2000))
    thrusts = np.array([table_thrust(p, c) for c in commands])
    assert np.all(np.diff(thrusts) >= 0)


def test_reverse_thrust_is_weaker_than_forward(t200):
    """The T200 is asymmetric: at the same distance from 1500 us reverse thrust is smaller than forward."""
    p = t200.as_array()
    for d in (100.0, 200.0, 300.0, 400.0):
        forward, reverse = table_thrust(p, 1500 + d), table_thrust(p, 1500 - d)
        assert reverse < 0 < forward and -reverse < forward
    assert -table_thrust(p, 1100.0) / table_thrust(p, 1900.0) == pytest.approx(4.0695 / 5.2450, abs=1e-4)


def test_inverse_gives_the_command_back_and_the_dead_band_centre_for_zero(t200):
    p = t200.as_array()
    assert table_command(p, 0.0) == 1500.0                    # dead band 1472-1528 us
    for c in np.linspace(1100, 1468, 37).tolist() + np.linspace(1532, 1900, 37).tolist():
        assert table_command(p, table_thrust(p, c)) == pytest.approx(c, abs=1e-9)
    assert table_command(p, 1e6) == 1900.0 and table_command(p, -1e6) == 1100.0


def test_first_order_lag_step_response_is_the_exponential(t200):
    """dT/dt = (T_ss - T)/tau from rest: T(t) = T_ss (1 - exp(-t/tau)), integrated by RK4 with h = tau/100."""
    p = t200.as_array()
    tau = t200.time_constant
    for command in (1900.0, 1100.0, 1650.0):
        T_ss = table_thrust(p, command)
        T, h = 0.0, tau / 100
        for _ in range(300):
            T = table_rk4_step(p, T, command, h)
        assert T == pytest.approx(T_ss * (1 - math.exp(-3.0)), rel=1e-9)
        assert table_exact(t200, 0.0, command, 3 * tau) == pytest.approx(T_ss * (1 - math.exp(-3.0)), rel=1e-14)


def test_a_table_built_in_code_and_its_refusals():
    params = TableThrusterParameters([0.0, 1.0, 2.0], [-1.0, 0.0, 3.0], time_constant=0.1)
    assert table_thrust(params.as_array(), 1.5) == pytest.approx(1.5)
    with pytest.raises(UvmsInputError, match="time_constant"):
        TableThrusterParameters([0.0, 1.0], [0.0, 1.0], time_constant=0.0)
    with pytest.raises(UvmsInputError, match="at least two"):
        TableThrusterParameters([0.0], [1.0], time_constant=0.1)


def write(tmp_path, text, name="thruster.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_csv_in_newtons_or_kgf(tmp_path):
    newtons = load_thruster_table(write(tmp_path, "# a comment\ncommand,thrust_N\n-1,-2\n0,0\n1,3\n"),
                                  time_constant=0.2, voltage=12.0)
    np.testing.assert_array_equal(newtons.thrust, [-2.0, 0.0, 3.0])
    assert newtons.voltage == 12.0 and newtons.source.endswith("thruster.csv")
    kgf = load_thruster_table(write(tmp_path, "\ufeffcommand_us,rpm,thrust_kgf\n1100,10,-1\n1900,20,2\n", "b.csv"),
                              time_constant=0.2)                 # with the byte-order mark spreadsheets write
    np.testing.assert_allclose(kgf.thrust, [-KGF, 2 * KGF], rtol=1e-15)


@pytest.mark.parametrize("text,field,message", [
    ("command,thrust_N\n0,0\n2,1\n1,2\n", "command", "increase strictly"),
    ("command,thrust_N\n0,0\n1,2\n2,1\n", "thrust_N", "must not decrease"),
    ("command,thrust_N\n0,0\n", "command", "at least two"),
    ("command,thrust_N\n0,0\n1,lots\n", "line 3, column thrust_N", "expected a number"),
    ("command,thrust_N\n0,0\n1,inf\n", "line 3, column thrust_N", "finite"),
    ("command,thrust_N\n0,0\n1\n", "line 3", "columns"),
    ("pwm,force\n0,0\n1,1\n", "line 1", "'command'"),
    ("# only comments\n", "header", "no data"),
])
def test_bad_csv_is_a_one_line_error_naming_file_and_field(tmp_path, text, field, message):
    path = write(tmp_path, text)
    with pytest.raises(UvmsInputError) as info:
        load_thruster_table(path, time_constant=0.1)
    line = str(info.value)
    assert "\n" not in line
    assert line.startswith(f"{path}: {field}: ") and message in line


def test_missing_csv_names_the_file(tmp_path):
    path = tmp_path / "absent.csv"
    with pytest.raises(UvmsInputError) as info:
        load_thruster_table(path, time_constant=0.1)
    assert str(info.value).startswith(f"{path}: cannot read")
