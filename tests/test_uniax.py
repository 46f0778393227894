"""YADE's concrete/uniax.py: its set-up helpers and its tension-compression test.

``utils.approxSectionArea`` and ``utils.uniaxialTestFeatures`` against real YADE 2023.02a
(tests/reference/yade/section_area.py, run unmodified under granum), and the CPM specimen's response on YADE's own
packing (tests/reference/yade/uniax_cpm.py): the physics judged apart from the random packing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import granum_reference_run, reference

#: the hull's area is a sum over its vertices, in another order than YADE's
AREA_RTOL = 1e-12


@pytest.fixture(scope="module")
def sections():
    return granum_reference_run("section_area.py"), reference("section_area")


def _close(got, ref, path=""):
    """Assert that two JSON-like records agree: numbers to AREA_RTOL, the rest exactly."""
    if isinstance(ref, dict):
        assert isinstance(got, dict) and set(got) == set(ref), path
        for k in ref:
            _close(got[k], ref[k], f"{path}/{k}")
    elif isinstance(ref, list):
        got = list(got)  # a Vector3 is a list in YADE's JSON
        assert len(got) == len(ref), path
        for k, (g, r) in enumerate(zip(got, ref, strict=True)):
            _close(g, r, f"{path}[{k}]")
    elif isinstance(ref, float):
        assert math.isclose(got, ref, rel_tol=AREA_RTOL, abs_tol=1e-12), f"{path}: granum {got!r}, YADE {ref!r}"
    else:
        assert got == ref, f"{path}: granum {got!r}, YADE {ref!r}"


@pytest.mark.parametrize("case", ["single", "outline", "pairs", "cloud", "columns", "empty"])
def test_sections_match_yade(sections, case):
    got, ref = sections
    _close(got[case], ref[case], case)


def test_section_errors(sections):
    got, ref = sections
    errors, ref_errors = got["errors"], ref["errors"]
    assert errors["area_axis3"]["exception"] == errors["area_axis-1"]["exception"] == "ValueError"
    assert ref_errors["area_axis3"]["exception"] == ref_errors["area_axis-1"]["exception"] == "ValueError"
    # YADE: AssertionError without a message, and NameError (spheresFromFile is gone from its utils)
    assert errors["features_axis3"] == {"exception": "ValueError",
                                        "message": "uniaxialTestFeatures: axis must be 0, 1 or 2, got 3"}
    assert errors["features_file"]["exception"] == "NotImplementedError"
    assert "spheres.txt" in errors["features_file"]["message"]


def test_section_area_hexagon_closed_form(yade):
    """One sphere's outline is the hexagon (cos k60, 2 sin k60) r: area 3 sqrt(3) r^2; two spheres d apart along
    u add d times its height along v (2 sqrt(3) r), along v d times its width (2 r)."""
    utils = yade.utils
    r, d = 0.3, 2.0
    yade.O.bodies.append(utils.sphere((1, 2, 3), r))
    for axis in range(3):
        assert utils.approxSectionArea((1, 2, 3)[axis] + 0.9 * r, axis) == pytest.approx(3 * math.sqrt(3) * r * r)
    shifted = np.array([1.0, 2.0, 3.0])
    shifted[0] += d  # along u of axis 2 (x), along v of axis 1 (z, x)
    yade.O.bodies.append(utils.sphere(tuple(shifted), r))
    assert utils.approxSectionArea(3, 2) == pytest.approx(3 * math.sqrt(3) * r * r + d * 2 * math.sqrt(3) * r)
    assert utils.approxSectionArea(2, 1) == pytest.approx(3 * math.sqrt(3) * r * r + d * 2 * r)
    assert utils.approxSectionArea(3 + 1.01 * r, 2) == 0.0


def test_uniaxial_features_refuse_what_yade_ignores(yade):
    yade.O.bodies.append(yade.utils.sphere((0, 0, 0), 1))
    with pytest.raises(ValueError, match="areaSections=5"):
        yade.utils.uniaxialTestFeatures(areaSections=5)
    with pytest.raises(NotImplementedError, match="foo"):
        yade.utils.uniaxialTestFeatures(foo=1)
    with pytest.raises(ValueError, match="coord must be finite"):
        yade.utils.approxSectionArea(float("nan"), 2)


# ---- UniaxialStrainer.setSpeeds ---------------------------------------------------------------------------------
def test_strainer_set_speeds_as_yade():
    """Every body's velocity and position after each of 3 steps: with setSpeeds the strainer's first run gives all
    live bodies the axial velocity v_n + rate (x - x_n0) (fixed ones too, other components kept); without it only
    the groups move. Closed forms: what YADE gives, to round-off."""
    got, ref = granum_reference_run("strainer_speeds.py"), reference("strainer_speeds")
    assert set(got) == set(ref)
    for case, r in ref.items():
        g = got[case]
        assert g["originalLength"] == pytest.approx(r["originalLength"], rel=1e-15), case
        assert g["strain"] == pytest.approx(r["strain"], rel=1e-12, abs=1e-15), case
        for gs, rs in zip(g["steps"], r["steps"], strict=True):
            np.testing.assert_allclose(np.array([list(v) for v in gs["vel"]]), rs["vel"], rtol=1e-12, atol=1e-15,
                                       err_msg=case)
            np.testing.assert_allclose(np.array([list(v) for v in gs["pos"]]), rs["pos"], rtol=1e-14, atol=1e-15,
                                       err_msg=case)


# ---- the CPM specimen on YADE's packing ----------------------------------------------------------------------
#: extremum stresses and the stress up to them: YADE's spread with another summation order (-j2 against -j1) and
#: granum's measured distance from YADE (0.1 % tension, 0.06 % compression; curves 0.04 % and 0.2 % of the peak)
PEAK_RTOL, CURVE_RTOL = 0.01, 0.005


@pytest.fixture(scope="module")
def uniax():
    from granum.cli import install_yade_alias

    install_yade_alias()  # the script imports yade.plot and yade.pack, as under the launcher
    return granum_reference_run("uniax_cpm.py"), reference("uniax_cpm")


def test_uniax_set_up_matches_yade(uniax):
    got, ref = uniax
    assert got["n"] == ref["n"] == 85
    _close(got["features"], ref["features"], "features")
    assert got["dt"] == pytest.approx(ref["dt"], rel=1e-14)
    assert got["area_50"] == pytest.approx(ref["area_50"], rel=AREA_RTOL)


@pytest.mark.parametrize("mode", ["tension", "compression"])
def test_uniax_peak_stress_matches_yade(uniax, mode):
    got, ref = uniax
    g, r = got[mode], ref[mode]
    assert g["peak"] == pytest.approx(r["peak"], rel=PEAK_RTOL)
    assert abs(g["iterPeak"] - r["iterPeak"]) <= 32  # two data points
    assert g["epsPeak"] == pytest.approx(r["epsPeak"], rel=0.02)
    # the stress-strain curve up to the peak, at the same steps (data every 16 steps from step 1 in both)
    n = r["i"].index(r["iterPeak"]) + 1
    assert g["i"][:n] == r["i"][:n]
    np.testing.assert_allclose(g["eps"][:n], r["eps"][:n], rtol=1e-9)  # positions summed in another order
    for key in ("sigma", "sigma50"):
        np.testing.assert_allclose(g[key][:n], r[key][:n], rtol=0, atol=CURVE_RTOL * abs(r["peak"]))
    # softening to half the peak ends both runs
    assert abs(g["sigma"][-1]) < 0.5 * abs(g["peak"])
