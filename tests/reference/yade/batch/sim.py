# A batch job that records what readParamsFromTable gave it (run by make_reference.py).
import json
readParamsFromTable(density=1000, initialVelocity=0, label='none', a=0, b='q', unknownOk=True)
from yade.params.table import *
tags = {k: O.tags[k] for k in ('line', 'description', 'params', 'defaultParams')}
tags['d.id=description.id'] = O.tags['d.id'] == O.tags['description'] + '.' + O.tags['id']
tags['id.d=id.description'] = O.tags['id.d'] == O.tags['id'] + '.' + O.tags['description']
out = dict(tags=tags, values=dict(density=density, initialVelocity=initialVelocity, label=label, a=a, b=b),
           batch=runningInBatch())
with open('job-%s.json' % O.tags['line'], 'w') as f:
    json.dump(out, f, indent=1, sort_keys=True)
