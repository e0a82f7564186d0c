"""Current profiles and gridded fields as inputs: the power law against its closed form, field files read back
to the arrays they were written from (CSV and NetCDF), and every refusal naming the file and the field."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from uvms.errors import UvmsInputError
from uvms.hydro.currents import (CurrentField, CurrentProfile, current_field, current_profile, power_law_profile,
                                 read_field, read_field_csv, read_field_netcdf)


def test_power_law_profile_against_its_closed_form():
    h, alpha, v0 = 20.0, 1.0 / 7.0, np.array([0.8, -0.3, 0.0])
    profile = power_law_profile(v0, h, alpha, points=101)
    assert isinstance(profile, CurrentProfile)
    assert profile.depth[0] == 0.0 and profile.depth[-1] == h and np.all(np.diff(profile.depth) > 0)
    d = np.linspace(0.0, h, 20001)
    law = ((h - d) / h) ** alpha                               # DNV-RP-C205 Eq. 4.1.3 written out
    for k in range(3):
        table = np.interp(d, profile.depth, profile.velocity[:, k])
        assert np.max(np.abs(table - v0[k] * law)) <= abs(v0[k]) / 100 + 1e-15
    assert np.allclose(profile.velocity[0], v0) and np.allclose(profile.velocity[-1], 0.0)


@pytest.mark.parametrize("args, match", [(([1, 0, 0], 0.0), "water depth"), (([1, 0, 0], 10.0, -0.5), "exponent"),
                                         (([math.nan, 0, 0], 10.0), "finite")])
def test_power_law_refusals(args, match):
    with pytest.raises(UvmsInputError, match=match):
        power_law_profile(*args)


@pytest.mark.parametrize("depth, velocity, field", [
    ([0.0, 2.0, 1.0], [[0, 0, 0]] * 3, "p.depth"),            # not increasing
    ([0.0, 1.0, 1.0], [[0, 0, 0]] * 3, "p.depth"),            # repeated
    ([0.0, math.nan], [[0, 0, 0]] * 2, "p.depth"),
    ([0.0, 1.0], [[0, 0, 0]], "p.velocity"),                  # a row short
    ([0.0, 1.0], [[0, 0, 0], [0, math.inf, 0]], "p.velocity"),
])
def test_profile_table_refusals_name_the_field(depth, velocity, field):
    with pytest.raises(UvmsInputError) as info:
        current_profile(depth, velocity, source="s.yaml", field="p")
    assert info.value.path == field and str(info.value).startswith("s.yaml: p.")


def _grid():
    x, y, z, t = np.array([0.0, 1.0, 3.0]), np.array([-1.0, 1.0]), np.array([0.0, 2.0, 4.0, 8.0]), np.array([0.0, 5.0])
    T, Z, Y, X = np.meshgrid(t, z, y, x, indexing="ij")
    velocity = np.stack([0.1 * X + 0.01 * T, -0.2 * Y + Z, 0.05 * Z * T], axis=-1)
    return x, y, z, t, velocity


def _write_csv(path, x, y, z, t, velocity, order=None, header="x,y,z,t,u,v,w"):
    rows = []
    for it, tv in enumerate(t):
        for iz, zv in enumerate(z):
            for iy, yv in enumerate(y):
                for ix, xv in enumerate(x):
                    u, v, w = velocity[it, iz, iy, ix]
                    rows.append([xv, yv, zv, tv, u, v, w])
    if order is not None:
        rows = [rows[k] for k in order(len(rows))]
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(c)) for c in r) for r in rows) + "\n")
    return rows


def test_csv_field_reads_back_its_grid_in_any_row_order(tmp_path):
    x, y, z, t, velocity = _grid()
    rng = np.random.default_rng(0)
    _write_csv(tmp_path / "f.csv", x, y, z, t, velocity, order=rng.permutation)
    field = read_field(tmp_path / "f.csv", "zero")
    assert isinstance(field, CurrentField) and field.outside == "zero"
    for got, want in zip(field[:4], (x, y, z, t)):
        assert np.array_equal(got, want)
    assert np.array_equal(field.velocity, velocity)


def test_csv_columns_in_another_order(tmp_path):
    x, y, z, t, velocity = _grid()
    rows = _write_csv(tmp_path / "a.csv", x, y, z, t, velocity)
    cols = ["t", "w", "x", "u", "z", "v", "y"]
    idx = [["x", "y", "z", "t", "u", "v", "w"].index(c) for c in cols]
    (tmp_path / "b.csv").write_text(",".join(cols) + "\n" + "\n".join(",".join(repr(float(r[k])) for k in idx)
                                                                       for r in rows))
    assert np.array_equal(read_field_csv(tmp_path / "b.csv").velocity, velocity)


def test_csv_refusals_name_the_file_and_the_place(tmp_path):
    x, y, z, t, velocity = _grid()
    path = tmp_path / "f.csv"
    rows = _write_csv(path, x, y, z, t, velocity)
    text = path.read_text().splitlines()

    def refused(lines, match):
        path.write_text("\n".join(lines) + "\n")
        with pytest.raises(UvmsInputError, match=match) as info:
            read_field_csv(path)
        assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)
        return info.value

    bad = text.copy()
    bad[3] = bad[3].replace(bad[3].split(",")[4], "nan", 1)
    assert refused(bad, "finite").path == "line 4, column u"
    assert refused(text[:1] + text[2:], "full grid").path == "rows"            # ragged: one point missing
    assert refused(text[:1] + [text[1]] + text[1:-1], "repeated").path == "rows"   # as many rows, one twice
    assert refused(["x,y,z,t,u,v"] + text[1:], "columns").path == "header"
    assert refused(text[:2] + ["1,2,3"], "expected 7 values").path == "line 3"
    assert refused(text[:2] + ["a,0,0,0,0,0,0"], "number").path == "line 3, column x"
    assert len(rows) == 48


def _netcdf(tmp_path, x, y, z, t, velocity, name="f.nc"):
    xarray = pytest.importorskip("xarray")
    dims = ("t", "z", "y", "x")
    data = xarray.Dataset({k: (dims, velocity[..., i]) for i, k in enumerate("uvw")},
                          coords={"x": x, "y": y, "z": z, "t": t})
    path = tmp_path / name
    data.to_netcdf(path, engine="scipy")
    return path


def test_netcdf_field_reads_back_its_arrays(tmp_path):
    x, y, z, t, velocity = _grid()
    field = read_field(_netcdf(tmp_path, x, y, z, t, velocity), "error")
    for got, want in zip(field[:4], (x, y, z, t)):
        assert np.array_equal(got, want)
    assert np.array_equal(field.velocity, velocity) and field.outside == "error"


def test_netcdf_with_dimensions_in_another_order_and_a_missing_one(tmp_path):
    xarray = pytest.importorskip("xarray")
    x, y, z, t, velocity = _grid()
    steady = velocity[:1]
    data = xarray.Dataset({"u": (("x", "y", "z"), steady[0, ..., 0].transpose(2, 1, 0)),
                           "v": (("z", "y", "x"), steady[0, ..., 1]), "w": (("z", "y", "x"), steady[0, ..., 2])},
                          coords={"x": x, "y": y, "z": z, "t": [0.0]})
    data.to_netcdf(tmp_path / "s.nc", engine="scipy")
    assert np.array_equal(read_field_netcdf(tmp_path / "s.nc").velocity, steady)


def test_netcdf_refusals(tmp_path):
    x, y, z, t, velocity = _grid()
    with pytest.raises(UvmsInputError, match="strictly increasing") as info:
        read_field_netcdf(_netcdf(tmp_path, x, y, z[::-1], t, velocity, "a.nc"))
    assert info.value.path == "z"
    nan = velocity.copy()
    nan[1, 2, 0, 1, 2] = math.nan
    with pytest.raises(UvmsInputError, match="finite velocities"):
        read_field_netcdf(_netcdf(tmp_path, x, y, z, t, nan, "b.nc"))


def test_netcdf_without_xarray_is_one_line(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)            # import xarray now raises ImportError
    with pytest.raises(UvmsInputError, match=r"needs xarray: pip install 'uvms\[netcdf\]'"):
        read_field_netcdf(tmp_path / "f.nc")


@pytest.mark.parametrize("change, field", [({"x": [0.0, 0.0, 1.0]}, "f.x"), ({"t": [1.0, 0.0]}, "f.t"),
                                           ({"outside": "wrap"}, "f.outside"), ({"velocity": np.zeros((2, 2))},
                                                                                "f.velocity")])
def test_field_array_refusals(change, field):
    x, y, z, t, velocity = _grid()
    args = {"x": x, "y": y, "z": z, "t": t, "velocity": velocity, "outside": "hold"} | change
    with pytest.raises(UvmsInputError) as info:
        current_field(**args, source="s.yaml", field="f")
    assert info.value.path == field


def test_unknown_field_file_suffix(tmp_path):
    with pytest.raises(UvmsInputError, match=".csv or .nc"):
        read_field(tmp_path / "f.txt")
