# Reference data for the modules yade.config, yade.math, yade.minieigenHP, yade.log, yade.libVersions
# (YADE 2023.02a, double build). Run: cd tests/reference/yade && yade -n -x namespace_modules.py
import os, sys, tempfile, types
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from _common import catch, dump
import yade.config, yade.math as m, yade.minieigenHP as mne, yade.log as L, yade.libVersions as lv

def public(mod):
    return {n: type(getattr(mod, n)).__name__ for n in dir(mod)
            if not n.startswith('_') and not isinstance(getattr(mod, n), types.ModuleType)}

config = {'names': public(yade.config), 'features': list(yade.config.features)}
for n in ('highPrecisionBits', 'highPrecisionDecimalPlaces', 'highPrecisionMpmath', 'highPrecisionName', 'suffix',
          'version', 'revision', 'libstdcxx'):
    config[n] = getattr(yade.config, n)
config['features_in_script_namespace'] = catch(lambda: features == yade.config.features)

R = m.RealHPConfig
reals = [0.5, -1.5, 2.75, 7.0, 13.3, -0.3]
one_arg = ['sin', 'sinh', 'cos', 'cosh', 'tan', 'tanh', 'abs', 'asinh', 'atan', 'cbrt', 'ceil', 'exp', 'exp2',
           'expm1', 'floor', 'lgamma', 'tgamma', 'erf', 'erfc', 'rint', 'round', 'trunc', 'fabs', 'frexp', 'modf',
           'sgn', 'sign', 'ilogb', 'logb', 'isinf', 'isnan', 'isfinite', 'roundTrip', 'toDouble', 'toLongDouble',
           'toLong', 'toInt', 'radians', 'degrees', 'Real', 'toHP1', 'log', 'log10', 'log1p', 'log2', 'sqrt', 'acos',
           'asin', 'atanh', 'acosh']
math = {'names': public(m), 'HP1_names': sorted(n for n in dir(m.HP1) if not n.startswith('_')),
        'RealHPConfig': {n: catch(lambda n=n: getattr(R, n)) for n in (
            'extraStringDigits10', 'isEnabledRealHP', 'isFloat128Broken', 'isFloat128Present',
            'workaroundSlowBoostBinFloat')},
        'RealHPConfig_getDigits10_1': R.getDigits10(1), 'RealHPConfig_getDigits2_1': R.getDigits2(1),
        'getDigits10_1': m.getDigits10(1), 'getDigits2_1': m.getDigits2(1),
        'needsMpmathAtN_1': m.needsMpmathAtN(1), 'usesHP': m.usesHP(),
        'traits': {n: getattr(m, n) for n in ('AddCost', 'MulCost', 'ReadCost', 'ComplexAddCost', 'ComplexMulCost',
                                              'ComplexReadCost', 'IsComplex', 'IsInteger', 'IsSigned',
                                              'RequireInitialization', 'defprec', 'max_exp2', 'hasInfinityNan')},
        'constants': {n: getattr(m, n)() for n in ('epsilon', 'dummy_precision', 'smallest_positive', 'highest',
                                                  'lowest', 'Pi', 'Euler', 'Log2', 'Catalan')},
        'one_arg': {f: [catch(lambda f=f, x=x: getattr(m, f)(x)) for x in reals] for f in one_arg},
        'one_arg_points': reals,
        'special_points': {f'{f}({x})': catch(lambda f=f, x=x: getattr(m, f)(float(x))) for f, x in [
            ('ilogb', 0), ('ilogb', 'inf'), ('ilogb', 'nan'), ('logb', 0), ('exp', 1000), ('log', 0), ('sqrt', -1),
            ('tgamma', 0), ('tgamma', -1), ('lgamma', 0), ('tgamma', 200), ('exp2', 2000), ('acos', 2),
            ('round', 2.5), ('round', -2.5), ('rint', 2.5), ('rint', 3.5), ('round', 0.49999999999999994)]},
        'two_arg': {f: [catch(lambda f=f, a=a, b=b: getattr(m, f)(a, b)) for a, b in [(7.0, 2.0), (5.5, -1.25), (-3.3, 0.7)]]
                    for f in ('atan2', 'fmod', 'hypot', 'max', 'min', 'pow', 'remainder', 'remquo', 'polar')},
        'ldexp': [m.ldexp(1.5, 3), m.ldexp(-0.75, -2)],
        'fma': [m.fma(2.0, 3.0, 4.0), m.fma(0.1, 10.0, -1.0)],
        'factorial': [m.factorial(n) for n in (0, 1, 5, 20)],
        'complex': {f: [catch(lambda f=f, z=z: complex(getattr(m, f)(z))) for z in (1 + 2j, -0.5 + 0.25j)]
                    for f in ('sin', 'sinh', 'cos', 'cosh', 'tan', 'tanh', 'asin', 'asinh', 'acos', 'acosh', 'atan',
                              'atanh', 'exp', 'log', 'log10', 'sqrt', 'conj', 'proj')},
        'complex_real': {f: [catch(lambda f=f, z=z: getattr(m, f)(z)) for z in (1 + 2j, -0.5 + 0.25j)]
                         for f in ('abs', 'arg', 'squaredNorm', 'real', 'imag')},
        'complex_pow': complex(m.pow(1 + 2j, 0.5 - 1j)),
        'cylBesselJ': {f'{n},{x}': catch(lambda n=n, x=x: m.cylBesselJ(n, x)) for n, x in [(0, 1.0), (1, 2.5), (2, 0.5), (3, -4.0), (5, 12.0), (0, 30.0)]},
        'laguerre': {f'{n},{k},{x}': m.laguerre(n, k, x) for n, k, x in [(2, 1, 0.5), (0, 0, 3.0), (4, 2, 1.7), (6, 0, -2.0)]},
        'sphericalHarmonic': {f'{n},{k},{t},{p}': complex(m.sphericalHarmonic(n, k, t, p)) for n, k, t, p in
                              [(2, 1, 0.3, 0.4), (0, 0, 1.0, 2.0), (3, -2, 0.7, 1.1), (4, 4, 2.0, -0.5), (3, 0, 2.5, 0.0)]},
        'fromBits': [m.fromBits('101'), m.fromBits('101', 3), m.fromBits('101', 0, -1), m.fromBits('1' * 53, -1)],
        'getRawBits': [m.getRawBits(1.5), m.getRawBits(-0.1)],
        'getDecomposedReal': [m.getDecomposedReal(1.5), m.getDecomposedReal(-0.1), m.getDecomposedReal(0.0)],
        'getFloatDistanceULP': [m.getFloatDistanceULP(1.0, 1.0000000000000002), m.getFloatDistanceULP(1.0, 0.9999999999999998),
                                m.getFloatDistanceULP(2.0, 1.0)],
        'names_demangled': [m.getDemangledName(), m.getDemangledNameComplex()],
        'fuzzy': {'isApprox': [m.isApprox(1.0, 1.0 + 1e-13, 1e-12), m.isApprox(1.0, 1.1, 1e-12)],
                  'isApproxOrLessThan': [m.isApproxOrLessThan(1.0, 2.0, 1e-12), m.isApproxOrLessThan(2.0, 1.0, 1e-12),
                                         m.isApproxOrLessThan(1.0 + 1e-13, 1.0, 1e-12)],
                  'isEqualFuzzy': [m.isEqualFuzzy(1.0, 1.0, 1e-12), m.isEqualFuzzy(1.0, 1.001, 1e-12)],
                  'isMuchSmallerThan': [m.isMuchSmallerThan(1e-20, 1.0, 1e-12), m.isMuchSmallerThan(0.5, 1.0, 1e-12)]},
        'Var': {'val': m.Var().val, 'cpl': complex(m.Var().cpl),
                'set_string': catch(lambda: setattr(m.Var(), 'val', 'abc'))},
        'linspace': [float(x) for x in m.linspace(0, 1, 5)],
        'getRealHPCppDigits10': m.getRealHPCppDigits10(), 'getRealHPPythonDigits10': m.getRealHPPythonDigits10(),
        'isThisSystemLittleEndian': m.isThisSystemLittleEndian()}

minieigen = {'names': sorted(n for n in dir(mne) if not n.startswith('_'))}

conf = os.path.join(tempfile.mkdtemp(), 'log.conf')
log = {'names': public(L), 'constants': {n: getattr(L, n) for n in ('TRACE', 'DEBUG', 'INFO', 'WARN', 'ERROR', 'FATAL', 'NOFILTER')},
       'default': L.getDefaultLogLevel(), 'used_initially': L.getUsedLevels(),
       'all_has_NewtonIntegrator': L.getAllLevels().get('NewtonIntegrator'),
       'setLevel_unknown': catch(lambda: L.setLevel('NoSuchClass', L.DEBUG)),
       'setLevel_99': catch(lambda: L.setLevel('NewtonIntegrator', 99)),
       'setLevel_str': catch(lambda: L.setLevel('NewtonIntegrator', 'x')),
       'setDefaultLogLevel_7': catch(lambda: L.setDefaultLogLevel(7)),
       'unsetLevel_unknown': catch(lambda: L.unsetLevel('NoSuchClass'))}
L.setLevel('NewtonIntegrator', L.DEBUG)
log['used_after_set'] = L.getUsedLevels()
L.saveConfigFile(conf)
log['config_file'] = open(conf).read().splitlines()
L.unsetLevel('NewtonIntegrator')
log['used_after_unset'] = L.getUsedLevels()
L.setDefaultLogLevel(L.INFO)
log['default_after_set'] = L.getDefaultLogLevel()
L.unsetLevel('Default')
log['default_after_unset'] = L.getDefaultLogLevel()
L.readConfigFile(conf)
log['used_after_read'] = L.getUsedLevels()

cpp, cmake = lv.getAllVersionsCpp(), lv.getAllVersionsCmake()
libversions = {'names': public(lv), 'cpp_python': cpp['python'], 'cpp_entry_types': sorted({type(v).__name__ for v in cpp.values()}),
               'getVersion_python': lv.getVersion('python'), 'getVersion_unknown': lv.getVersion('nonexist'),
               'getArchitecture': lv.getArchitecture(), 'getLinuxVersion': lv.getLinuxVersion(),
               'getAllVersions_type': type(lv.getAllVersions()).__name__,
               'printAllVersions_returns': catch(lambda: lv.printAllVersions())}

dump('namespace_modules', {'config': config, 'math': math, 'minieigenHP': minieigen, 'log': log, 'libVersions': libversions})
