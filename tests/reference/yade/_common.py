# Shared helpers for the YADE reference scripts in this directory (YADE 2023.02a).
# Not a reference script itself: imported by the <topic>.py scripts.
# Conventions: Vector* -> list, Matrix* -> list of rows, Quaternion -> [w, x, y, z],
# anything not JSON-serialisable -> repr() without ' at 0x...' addresses; floats inf/nan are written as
# Infinity/NaN (Python's json default, readable by json.load).
import json
import os
import re
import sys


def tojson(v):
    name = type(v).__name__
    if name == 'Quaternion':
        return [float(v[3]), float(v[0]), float(v[1]), float(v[2])]
    if name.startswith('Matrix'):
        return [[float(v[i, j]) for j in range(v.cols())] for i in range(v.rows())]
    if name.startswith('Vector'):
        return [int(x) if name.endswith('i') else float(x) for x in v]
    if v is None or isinstance(v, (bool, int, str)):
        return v
    if isinstance(v, float):
        return v
    if isinstance(v, (list, tuple)):
        return [tojson(x) for x in v]
    if isinstance(v, dict):
        return {str(k): tojson(x) for k, x in v.items()}
    try:  # numpy / mpmath-like scalars
        return float(v)
    except Exception:
        return re.sub(r' at 0x[0-9a-f]+', '', repr(v))  # drop addresses: stable output

def catch(fn):
    """Run fn(); return its (converted) value or {'exception': cls, 'message': str}."""
    try:
        return tojson(fn())
    except Exception as e:
        return {'exception': type(e).__name__, 'message': str(e)}

def dump(topic, data):
    path = os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), topic + '.json')
    with open(path, 'w') as f:
        f.write(_fmt(tojson(data)) + '\n')
    print('wrote', path)

def _fmt(v, ind=0):
    """json with indentation, but lists of scalars (and lists of such lists) on one line."""
    pad = ' ' * (ind + 1)
    if isinstance(v, dict):
        if not v:
            return '{}'
        items = [pad + json.dumps(k) + ': ' + _fmt(x, ind + 1) for k, x in v.items()]
        return '{\n' + ',\n'.join(items) + '\n' + ' ' * ind + '}'
    if isinstance(v, list):
        flat = lambda x: not isinstance(x, (list, dict)) or (isinstance(x, list) and all(not isinstance(y, (list, dict)) for y in x))
        if all(flat(x) for x in v):
            return json.dumps(v)
        return '[\n' + ',\n'.join(pad + _fmt(x, ind + 1) for x in v) + '\n' + ' ' * ind + ']'
    return json.dumps(v)
