"""YADE bodies from a rockslice model, in-process: inside a yade script (yade -n -x script.py),

    import rockslice, rockslice.yade
    model = rockslice.slice('scene.toml')
    bodies = rockslice.yade.build(model, steps=1000)

builds what slice-export --format yade writes into model.py, by the same program
(rockslice/yade_program.py, which slice-export embeds): one Polyhedra body and one material per
block that is not removed, fixed boundary and fixed_faces blocks, a clump per cluster (fixed if
it holds a fixed block), the engines of a settling run under gravity along -z and the time step
of the smallest body that moves; steps > 0 runs that many steps. A 2-D section becomes prisms of
unit thickness that move in (x, z). The options are slice-export's --yade-* options.
"""
import os

from . import _rockslice

PROGRAM = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'yade_program.py')
#: The options and their defaults (slice-export's --yade-density, --yade-young, ...).
DEFAULTS = _rockslice._yade_options()


class Bodies:
    """What build() made: body_of_block (block id -> YADE body id), clump_of_cluster (cluster
    -> clump body id), dt (O.dt), smallest (volume of the smallest body that moves) and
    namespace (every name the program defined)."""

    def __init__(self, ns):
        self.namespace = ns
        self.body_of_block = ns['body_of_block']
        self.clump_of_cluster = ns['clump_of_cluster']
        self.smallest = ns['smallest']
        self.dt = ns['O'].dt if 'O' in ns else None

    def __repr__(self):
        return '<rockslice.yade.Bodies: %d blocks, %d clumps>' % (len(self.body_of_block),
                                                                  len(self.clump_of_cluster))


def build(model, steps=0, engines=True, initial_gap=_rockslice.YADE_INITIAL_GAP,
          law='mohr-coulomb', **options):
    """Adds the model's blocks to YADE's scene (O) as the exported script does; returns Bodies.

    model: a rockslice.Model with vertices (stage 'geometry'); steps: run this many steps of the
    settling run at the end; engines=False leaves O.engines and O.dt alone; initial_gap: each
    body is its block scaled by 1 - initial_gap about its centroid (0: the blocks as they are);
    law: the contact law, 'mohr-coulomb' (each contact its joint's strength and its own shear
    force) or 'volumetric' (YADE's own law alone; slice-export's --yade-law);
    options: density, young, poisson, default_friction, damping, gravity, timestep_factor
    (DEFAULTS). Raises rockslice.Error for a bad option or a model without vertices.
    """
    try:
        import yade  # noqa: F401 (only inside yade)
    except ImportError:
        raise ImportError('rockslice.yade.build runs inside YADE: put it in a script and run '
                          'yade -n -x script.py') from None
    unknown = sorted(set(options) - set(DEFAULTS))
    if unknown:
        raise TypeError('build() got unknown options %s; the options are %s'
                        % (', '.join(unknown), ', '.join(sorted(DEFAULTS))))
    try:
        opt = _rockslice._yade_options(steps=steps, law=str(law), **options)
    except _rockslice.Error as e:
        # The library names slice-export's options (--yade-density): name the keyword instead.
        raise _rockslice.Error(str(e).replace('--yade-friction', 'default_friction')
                               .replace('--yade-timestep-factor', 'timestep_factor')
                               .replace('--yade-', '')) from None
    if not 0 <= initial_gap < 1:
        raise _rockslice.Error('initial_gap: is %r; give a fraction in [0, 1)' % (initial_gap,))
    rows = model._yade_rows(opt['default_friction'])
    ns = {
        '__name__': 'rockslice_yade_model',
        'BLOCKS': rows,
        'SOURCE': model.provenance.get('input', ''),
        'STEPS': int(opt['steps']),
        'DENSITY': opt['density'],
        'YOUNG': opt['young'],
        'POISSON': opt['poisson'],
        'DEFAULT_FRICTION_DEG': opt['default_friction'],
        'DAMPING': opt['damping'],
        'GRAVITY': opt['gravity'],
        'TIMESTEP_FACTOR': opt['timestep_factor'],
        'INITIAL_GAP': float(initial_gap),
        'SHAPE': 'polyhedra',
        'LAW': opt['law'],
        'CONTACTS': model._yade_contacts(),
        'SECTION': model.dimension == 2,
        'ENGINES': bool(engines),
    }
    with open(PROGRAM) as f:
        code = compile(f.read(), PROGRAM, 'exec')
    exec(code, ns)
    return Bodies(ns)
