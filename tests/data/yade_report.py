# Runs a rockslice YADE model inside YADE and writes what the tests check to a JSON file:
#   yade -n -x tests/data/yade_report.py model.py report.json
# `yade -x` exits with 0 even when the script raises, so a failure is written to the report
# ("error") and the test reads it there.
import json
import math
import sys
import traceback

model, report = sys.argv[1], sys.argv[2]
out = {}
try:
    exec(compile(open(model).read(), model, 'exec'))
    out = {'iterations': O.iter, 'dt': O.dt, 'bodies': [],
           'body_of_block': {str(k): v for k, v in body_of_block.items()},
           'clump_of_cluster': {str(k): v for k, v in clump_of_cluster.items()},
           # cluster members too small to be bodies: block -> the member that took their mass
           'merged_into': {str(k): v for k, v in globals().get('merged_into', {}).items()},
           # Polyhedra scripts only: the relative gap the bodies start with (SHRINK = 1 - gap)
           'initial_gap': globals().get('INITIAL_GAP', 0.0),
           'real_interactions': O.interactions.countReal(),
           'law': globals().get('LAW', ''),
           'contacts': len(globals().get('CONTACTS', [])),
           # every pair the collider holds, real or not: [id1, id2]
           'pairs': [[i.id1, i.id2] for i in O.interactions.all(False)]}
    for b in O.bodies:
        row = {'id': b.id, 'is_clump': b.isClump,
               'clump': b.clumpId if b.isClumpMember else -1,
               # NaN is not JSON: a non-finite coordinate becomes null
               'pos': [x if math.isfinite(x) else None for x in b.state.pos],
               'blocked': b.state.blockedDOFs,
               'mass': b.state.mass}
        if not b.isClump:
            row['volume'] = b.shape.GetVolume()
            # The block's own angle: its material's under LAW 'volumetric'; under 'mohr-coulomb'
            # (material angle 0: the law's engine gives the shear) the angle the law falls back
            # on for a contact CONTACTS does not list.
            if globals().get('LAW', 'volumetric') == 'mohr-coulomb':
                row['friction_deg'] = math.degrees(math.atan(tan_of_body[b.id]))
                row['material_friction_deg'] = math.degrees(b.mat.frictionAngle)
            else:
                row['friction_deg'] = b.mat.frictionAngle * 180 / 3.141592653589793
        out['bodies'].append(row)
except BaseException:
    out = {'error': traceback.format_exc()}
with open(report, 'w') as f:
    json.dump(out, f)
