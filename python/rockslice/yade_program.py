# The program of rockslice's YADE models: bodies, materials, clumps, fixed blocks, engines and
# the settling run, by the rules of the export (rockslice README, "YADE models").
# One text, two users: slice-export --format yade / yade-potential-blocks writes it into the
# script after the constants and BLOCKS (the build embeds this file in the library), and
# rockslice.yade.build() runs it inside YADE on a model in memory. It is no module to import:
# it needs these names first:
#   SHAPE    'polyhedra' (Polyhedra bodies) or 'potential_blocks' (PotentialBlock bodies: a YADE
#            built with ENABLE_POTENTIAL_BLOCKS)
#   BLOCKS   one row per block that is not removed: (block id, fixed, friction angle [deg],
#            cluster (-1: none), volume, centroid, vertices (global)) for polyhedra;
#            (..., volume, inscribed radius, bounding radius, centroid, planes) for
#            potential_blocks
#   SOURCE, STEPS, DENSITY, YOUNG, POISSON, DEFAULT_FRICTION_DEG, DAMPING, GRAVITY,
#   TIMESTEP_FACTOR, and INITIAL_GAP (polyhedra) or PB_ROUNDING (potential_blocks): the
#            export's options; see the constants of model.py
#   SECTION  True for a 2-D section (docs/2d.md; polyhedra only): bodies move in (x, z) only
#   ENGINES  True: set O.engines and O.dt (the export always does)
import math
import time
from yade import *  # noqa: F401,F403 (the names YADE gives every script)
from yade import log
from yade.minieigenHP import Vector3

body_of_block = {}
started = time.time()
def progress(what):
    print('rockslice: %s (%.0f s)' % (what, time.time() - started), flush=True)
progress('building %d bodies' % len(BLOCKS))
if SHAPE == 'polyhedra':
    from yade import polyhedra_utils
    # Neighbouring blocks share faces exactly. YADE's Polyhedra contact (Ig2) then intersects
    # every touching pair with CGAL at every step, for a volume of rounding size (about 4 times
    # the cost of a pair that is apart; docs/yade-speed.md). So each body is its block scaled by
    # SHRINK about the block's centroid: faces that touched open by INITIAL_GAP x the sum of the
    # two centroids' distances to the face (1e-6 of the blocks' size), and the density is
    # divided by SHRINK^3 so that every body keeps its block's mass. INITIAL_GAP = 0 gives the
    # touching blocks back.
    SHRINK = 1 - INITIAL_GAP
    # Two fixed bodies never move, so their contact does nothing: fixed bodies (and the members
    # of a fixed clump) get FIXED_MASK, which the collider's avoidSelfInteractionMask keeps
    # apart, and free bodies FREE_MASK, which meets both. NOT_AMONG_FIXED = 0 pairs fixed bodies
    # again.
    FREE_MASK, FIXED_MASK = 1, 3
    NOT_AMONG_FIXED = 2  # the collider's avoidSelfInteractionMask
    for i, (block, fixed, phi, cluster, volume, centroid, vertices) in enumerate(BLOCKS):
        mat = PolyhedraMat(young=YOUNG, poisson=POISSON, frictionAngle=math.radians(phi),
                           density=DENSITY / SHRINK ** 3, label='block-%d' % block)
        O.materials.append(mat)
        grey = 0.35 if fixed else 0.75
        c = Vector3(centroid)
        shape = [c + SHRINK * (Vector3(p) - c) for p in vertices] if INITIAL_GAP else vertices
        body = polyhedra_utils.polyhedra(mat, v=shape, fixed=bool(fixed),
                                         color=(grey, grey, grey),
                                         mask=FIXED_MASK if fixed else FREE_MASK)
        if SECTION and not fixed:
            body.state.blockedDOFs = 'yXZ'  # the section's plane (x, z): no y, no turning off it
        body_of_block[block] = O.bodies.append(body)
        if (i + 1) % max(1, len(BLOCKS) // 10) == 0:
            progress('%d of %d bodies' % (i + 1, len(BLOCKS)))
else:
    from yade import potential_utils
    for i, (block, fixed, phi, cluster, volume, inradius, radius, centroid,
            planes) in enumerate(BLOCKS):
        mat = FrictMat(young=-1, poisson=-1, frictionAngle=math.radians(phi), density=DENSITY,
                       label='block-%d' % block)
        O.materials.append(mat)
        r = PB_ROUNDING * inradius
        grey = 0.35 if fixed else 0.75
        body = potential_utils.potentialblock(
            mat, a=[p[0] for p in planes], b=[p[1] for p in planes], c=[p[2] for p in planes],
            d=[p[3] - r for p in planes], r=r, R=radius, isBoundary=bool(fixed),
            fixed=bool(fixed), color=[grey, grey, grey])
        body.state.pos = Vector3(centroid) + body.shape.position
        body_of_block[block] = O.bodies.append(body)
        if (i + 1) % max(1, len(BLOCKS) // 10) == 0:
            progress('%d of %d bodies' % (i + 1, len(BLOCKS)))

# Clusters become clumps; a clump with a fixed (boundary) member is fixed as a whole.
members_of_cluster = {}
fixed_cluster = set()
for row in BLOCKS:
    block, fixed, cluster = row[0], row[1], row[3]
    if cluster >= 0:
        members_of_cluster.setdefault(cluster, []).append(body_of_block[block])
        if fixed:
            fixed_cluster.add(cluster)
clump_of_cluster = {}
for cluster in sorted(members_of_cluster):
    members = members_of_cluster[cluster]
    if len(members) < 2:
        continue
    clump = O.bodies.clump(members)
    if cluster in fixed_cluster:
        O.bodies[clump].state.blockedDOFs = 'xyzXYZ'
        if SHAPE == 'polyhedra':
            for member in members:
                O.bodies[member].mask = FIXED_MASK
    elif SECTION:
        O.bodies[clump].state.blockedDOFs = 'yXZ'
    clump_of_cluster[cluster] = clump
progress('%d clumps' % len(clump_of_cluster))

# The volume of each rigid body: a clump moves as one, so its thin members (pieces cut off by a
# construction joint exempt from the size limit) do not set the time step; its whole volume does.
# Fixed bodies never move and set none: the smallest body that moves does (slice-export and
# slice-info report the same figure).
volume_of_body = {}
fixed_body = set()
for row in BLOCKS:
    body = ('clump', row[3]) if row[3] in clump_of_cluster else ('block', row[0])
    volume_of_body[body] = volume_of_body.get(body, 0.0) + row[4]
    if row[1]:
        fixed_body.add(body)
moving = [v for body, v in volume_of_body.items() if body not in fixed_body]
smallest = min(moving) if moving else 1.0

# The smallest body sets the verlet distance and the time step: a contact as large as a face,
# A ~ V^(2/3), has stiffness k = YOUNG A (the volumetric law's, or kn per unit area) against
# m = DENSITY V, dt = sqrt(m / k). (polyhedra_utils.PWaveTimeStep() looks at spheres only and
# returns 1 s.)
if ENGINES and SHAPE == 'polyhedra':
    # YADE's Polyhedra contact test warns "Unhandled switch case:0" for every new pair of
    # blocks (its separating-plane cache starts empty); blocks that touch face to face make many.
    log.setLevel('Polyhedra_support.cpp', log.ERROR)
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0.01 * smallest ** (1.0 / 3),
                              avoidSelfInteractionMask=NOT_AMONG_FIXED),
        InteractionLoop(
            [Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
            [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
            [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()],
        ),
        NewtonIntegrator(damping=DAMPING, gravity=(0, 0, -GRAVITY), label='newton'),
    ]
elif ENGINES:
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([PotentialBlock2AABB()],
                              verletDist=0.01 * smallest ** (1.0 / 3)),
        InteractionLoop(
            [Ig2_PB_PB_ScGeom(twoDimension=False, calContactArea=True)],
            [Ip2_FrictMat_FrictMat_KnKsPBPhys(kn_i=YOUNG, ks_i=POISSON * YOUNG, Knormal=YOUNG,
                                              Kshear=POISSON * YOUNG, useFaceProperties=False,
                                              viscousDamping=DAMPING)],
            [Law2_SCG_KnKsPBPhys_KnKsPBLaw(label='law', neverErase=False)],
        ),
        NewtonIntegrator(damping=DAMPING, exactAsphericalRot=True, gravity=(0, 0, -GRAVITY),
                         label='newton'),
    ]
if ENGINES:
    O.dt = TIMESTEP_FACTOR * math.sqrt(DENSITY * smallest ** (1.0 / 3) / YOUNG)

if STEPS > 0:
    # Step progress: 20 lines over the run. (The command runs in YADE's own namespace: it
    # imports what it uses.)
    O.engines = O.engines + [PyRunner(iterPeriod=max(1, STEPS // 20), command=(
        "import time; print('rockslice: step %d of " + str(STEPS) + " (%.0f s)' % (O.iter + 1, "
        "time.time() - " + repr(time.time()) + "), flush=True)"))]
    progress('running %d steps, dt = %.3g s' % (STEPS, O.dt))
    O.run(STEPS, True)
    progress('done')
