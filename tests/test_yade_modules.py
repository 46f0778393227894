"""yade.config, yade.math, yade.minieigenHP, yade.log and yade.libVersions against real YADE 2023.02a
(tests/reference/yade/namespace_modules.json, written by namespace_modules.py under ``yade -n -x``)."""

import cmath
import json
import logging
import math
import os

import pytest

from granum import yade as gy
from granum.yade import config, libVersions, log, minieigenHP
from granum.yade import math as ymath

REF = json.load(open(os.path.join(os.path.dirname(__file__), "reference", "yade", "namespace_modules.json")))
M = REF["math"]


def close(a, b, rel=4 * 2.220446049250313e-16):
    if isinstance(b, float) and math.isnan(b):
        return math.isnan(a)
    return a == b or math.isclose(a, b, rel_tol=rel, abs_tol=1e-300)


# yade.config

def test_config_has_yades_names_with_yades_types():
    for name, type_name in REF["config"]["names"].items():
        assert type(getattr(config, name)).__name__ == type_name, name


def test_config_precision_is_yades_double_build():
    for name in ("highPrecisionDecimalPlaces", "highPrecisionName", "libstdcxx"):
        assert getattr(config, name) == REF["config"][name]
    # YADE's double build also offers long double through mpmath; granum has doubles only
    assert REF["config"]["highPrecisionMpmath"] is True and config.highPrecisionMpmath is False


def test_features_spelled_as_yade_and_in_the_script_namespace():
    assert set(config.features) <= set(REF["config"]["features"])
    assert all(f.isupper() for f in config.features)
    assert REF["config"]["features_in_script_namespace"] is True
    assert gy.namespace()["features"] is config.features
    assert "QT5" not in config.features and "CGAL" not in config.features


def test_script_namespace_math_is_pythons_and_yade_math_is_the_module():
    assert gy.namespace()["math"] is math
    assert gy.math is ymath


# yade.math

def test_math_has_yades_hp1_functions():
    yade_hp1 = set(M["HP1_names"]) - {n for n in M["HP1_names"] if n.startswith("CGAL_")} - {"toHP2"}
    assert yade_hp1 <= set(dir(ymath.HP1))
    assert not any(n.startswith("CGAL_") for n in dir(ymath)) and ymath.testCgalNumTraits is False


def test_math_traits_and_constants():
    for name, value in M["traits"].items():
        assert getattr(ymath, name) == value, name
    for name, value in M["constants"].items():
        assert getattr(ymath, name)() == value, name
    assert ymath.getDigits10(1) == M["getDigits10_1"] and ymath.getDigits2(1) == M["getDigits2_1"]
    assert ymath.RealHPConfig.getDigits10(1) == M["RealHPConfig_getDigits10_1"]
    assert ymath.RealHPConfig.extraStringDigits10 == M["RealHPConfig"]["extraStringDigits10"]
    assert ymath.needsMpmathAtN(1) is M["needsMpmathAtN_1"] and ymath.usesHP() is M["usesHP"]
    with pytest.raises(NotImplementedError, match="RealHP<2>"):
        ymath.getDigits10(2)


@pytest.mark.parametrize("name", sorted(M["one_arg"]))
def test_math_one_argument_functions(name):
    for x, expected in zip(M["one_arg_points"], M["one_arg"][name], strict=True):
        got = getattr(ymath, name)(x)
        if isinstance(expected, dict):  # YADE raised
            continue
        if isinstance(expected, list):
            assert list(got) == pytest.approx(expected, rel=1e-15), (name, x)
        elif name in ("lgamma", "tgamma", "erfc"):
            assert close(got, expected, rel=1e-13), (name, x)
        else:
            assert close(got, expected), (name, x, got, expected)
            assert type(got) is type(expected) or isinstance(expected, float), (name, type(got))


def test_math_c_semantics_at_the_edges():
    for call, expected in M["special_points"].items():
        name, arg = call[:-1].split("(")
        assert close(getattr(ymath, name)(float(arg)), expected), call


@pytest.mark.parametrize("name", sorted(M["two_arg"]))
def test_math_two_argument_functions(name):
    for (a, b), expected in zip([(7.0, 2.0), (5.5, -1.25), (-3.3, 0.7)], M["two_arg"][name], strict=True):
        got = getattr(ymath, name)(a, b)
        if name == "remquo":
            assert close(got[0], expected[0]) and got[1] % 8 == expected[1] % 8
        elif name == "polar":
            assert cmath.isclose(got, complex(expected.replace(" ", "")) if isinstance(expected, str) else expected)
        else:
            assert close(got, expected), (name, a, b)


def test_math_complex_overloads():
    for name, values in M["complex"].items():
        for z, expected in zip((1 + 2j, -0.5 + 0.25j), values, strict=True):
            assert cmath.isclose(complex(getattr(ymath, name)(z)), complex(expected), rel_tol=1e-15), name
    for name, values in M["complex_real"].items():
        for z, expected in zip((1 + 2j, -0.5 + 0.25j), values, strict=True):
            assert close(getattr(ymath, name)(z), expected), name
    assert cmath.isclose(ymath.pow(1 + 2j, 0.5 - 1j), complex(M["complex_pow"]), rel_tol=1e-15)


def test_math_small_helpers():
    assert [ymath.ldexp(1.5, 3), ymath.ldexp(-0.75, -2)] == M["ldexp"]
    assert [ymath.fma(2.0, 3.0, 4.0), ymath.fma(0.1, 10.0, -1.0)] == M["fma"]
    assert [ymath.factorial(n) for n in (0, 1, 5, 20)] == M["factorial"]
    assert list(ymath.linspace(0, 1, 5)) == M["linspace"]
    assert list(ymath.getRealHPCppDigits10()) == M["getRealHPPythonDigits10"][:1]
    assert ymath.isThisSystemLittleEndian() is M["isThisSystemLittleEndian"]
    for name, values in M["fuzzy"].items():
        args = {"isApprox": [(1.0, 1.0 + 1e-13), (1.0, 1.1)], "isApproxOrLessThan": [(1.0, 2.0), (2.0, 1.0),
                (1.0 + 1e-13, 1.0)], "isEqualFuzzy": [(1.0, 1.0), (1.0, 1.001)],
                "isMuchSmallerThan": [(1e-20, 1.0), (0.5, 1.0)]}[name]
        assert [getattr(ymath, name)(a, b, 1e-12) for a, b in args] == values, name


def test_math_special_functions():
    for key, expected in M["laguerre"].items():
        n, k, x = key.split(",")
        assert close(ymath.laguerre(int(n), int(k), float(x)), expected, rel=1e-14), key
    for key, expected in M["sphericalHarmonic"].items():
        n, k, t, p = key.split(",")
        got = ymath.sphericalHarmonic(int(n), int(k), float(t), float(p))
        assert cmath.isclose(got, complex(expected), rel_tol=1e-13, abs_tol=1e-16), key
    finite = {k: v for k, v in M["cylBesselJ"].items() if not math.isnan(v)}
    assert finite  # YADE's double build gives NaN for most of these points; granum gives the value
    for key, expected in finite.items():
        n, x = key.split(",")
        assert close(ymath.cylBesselJ(int(n), float(x)), expected, rel=1e-14), key
    assert ymath.cylBesselJ(1, 2.5) == pytest.approx(0.4970941024642741, rel=1e-14)  # tables (A&S 9.1)


def test_math_binary_representation():
    assert [ymath.fromBits("101"), ymath.fromBits("101", 3), ymath.fromBits("101", 0, -1),
            ymath.fromBits("1" * 53, -1)] == M["fromBits"]
    assert [ymath.getRawBits(1.5), ymath.getRawBits(-0.1)] == M["getRawBits"]
    assert [ymath.getDecomposedReal(x) for x in (1.5, -0.1, 0.0)] == M["getDecomposedReal"]
    assert [ymath.getFloatDistanceULP(1.0, 1.0000000000000002), ymath.getFloatDistanceULP(1.0, 0.9999999999999998),
            ymath.getFloatDistanceULP(2.0, 1.0)] == M["getFloatDistanceULP"]
    assert [ymath.getDemangledName(), ymath.getDemangledNameComplex()] == M["names_demangled"]


def test_math_var_and_self_checks():
    var = ymath.Var()
    assert var.val == M["Var"]["val"] and var.cpl == complex(M["Var"]["cpl"])
    assert "exception" in M["Var"]["set_string"]
    with pytest.raises(TypeError):
        var.val = "abc"
    ymath.testLoopRealHP()
    with pytest.raises(NotImplementedError, match="getRealHPErrors"):
        ymath.getRealHPErrors([1])


# yade.minieigenHP

def test_minieigen_types_are_granums_and_a_subset_of_yades():
    present = {n for n in dir(minieigenHP) if not n.startswith("_") and n[0].isupper() and n != "HP1"}
    assert present <= set(REF["minieigenHP"]["names"])
    assert minieigenHP.Vector3 is gy.Vector3 and minieigenHP.HP1.Quaternion is gy.Quaternion
    assert minieigenHP.vectorize is False and minieigenHP.HP1.vectorize is False


# yade.log

def test_log_constants_and_names():
    L = REF["log"]
    assert {n: getattr(log, n) for n in L["constants"]} == L["constants"]
    assert {n for n, t in L["names"].items() if t == "function"} <= set(dir(log))


@pytest.fixture
def fresh_log():
    log.setDefaultLogLevel(REF["log"]["default"])
    yield
    log.unsetLevel("NewtonIntegrator")
    log.setDefaultLogLevel(REF["log"]["default"])
    log.resetOutputStream()
    log.setUseColors(True)


def test_log_levels_as_yade(fresh_log, tmp_path):
    L = REF["log"]
    assert log.getDefaultLogLevel() == L["default"] and log.getUsedLevels() == L["used_initially"]
    assert log.getAllLevels()["NewtonIntegrator"] == L["all_has_NewtonIntegrator"]
    for key, call in (("setLevel_unknown", lambda: log.setLevel("NoSuchClass", log.DEBUG)),
                      ("setLevel_99", lambda: log.setLevel("NewtonIntegrator", 99)),
                      ("setDefaultLogLevel_7", lambda: log.setDefaultLogLevel(7)),
                      ("unsetLevel_unknown", lambda: log.unsetLevel("NoSuchClass"))):
        with pytest.raises(RuntimeError) as raised:
            call()
        assert type(raised.value).__name__ == L[key]["exception"]
    with pytest.raises(TypeError):  # YADE: Boost.Python's ArgumentError, a TypeError
        log.setLevel("NewtonIntegrator", "x")
    log.setLevel("NewtonIntegrator", log.DEBUG)
    assert log.getUsedLevels() == L["used_after_set"]
    conf = str(tmp_path / "log.conf")
    log.saveConfigFile(conf)
    assert open(conf).read().splitlines() == L["config_file"]
    log.unsetLevel("NewtonIntegrator")
    assert log.getUsedLevels() == L["used_after_unset"]
    log.setDefaultLogLevel(log.INFO)
    assert log.getDefaultLogLevel() == L["default_after_set"]
    log.readConfigFile(conf)
    assert log.getUsedLevels() == L["used_after_read"]


def test_log_filters_python_records(fresh_log, tmp_path):
    out = tmp_path / "out.log"
    log.setUseColors(False)
    log.setOutputStream(str(out), True)
    logger = logging.getLogger("granum.NewtonIntegrator")
    logger.info("hidden at WARN")
    log.setLevel("NewtonIntegrator", log.INFO)
    logger.info("shown at INFO")
    log.testAllLevels()
    text = out.read_text()
    assert "hidden" not in text and "<INFO> NewtonIntegrator: shown at INFO" in text
    assert "LOG_3_WARNING" in text and "LOG_4" not in text  # testAllLevels under Default = WARN


# yade.libVersions

def test_libversions_structure():
    V = REF["libVersions"]
    assert {n for n in V["names"]} <= set(dir(libVersions))
    cpp = libVersions.getAllVersionsCpp()
    assert {type(v).__name__ for v in cpp.values()} == set(V["cpp_entry_types"])
    assert len(cpp["python"][0]) == len(V["cpp_python"][0]) and isinstance(cpp["python"][1], str)
    assert libVersions.getVersion("python") == cpp["python"][0]
    assert libVersions.getVersion("nonexist") == V["getVersion_unknown"]
    assert libVersions.getVersion("numpy") == libVersions.getAllVersionsCmake()["numpy"][0]
    assert libVersions.getArchitecture() == V["getArchitecture"]  # both ran on this machine
    assert type(libVersions.getAllVersions()).__name__ == V["getAllVersions_type"]
    assert libVersions.printAllVersions() == V["printAllVersions_returns"]
