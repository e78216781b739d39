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
#   CONTACTS one row per contact of two kept blocks across a joint (polyhedra): (block a,
#            block b, friction angle [deg], cohesion [Pa], tension [Pa], area, centroid, normal
#            from a to b); LAW 'mohr-coulomb' gives each its joint's strength (docs/dem-exports.md)
#   LAW      polyhedra: 'mohr-coulomb' (rockslice's per-contact law) or 'volumetric' (YADE's own
#            Law2_PolyhedraGeom_PolyhedraPhys_Volumetric alone: its shear is wrong for a body with
#            two or more contacts)
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

rows_of_cluster = {}
for row in BLOCKS:
    if row[3] >= 0:
        rows_of_cluster.setdefault(row[3], []).append(row)

# The volume of each rigid body: a cluster of two or more blocks moves as one, so its thin
# members (pieces cut off by a construction joint exempt from the size limit) do not set the
# time step; its whole volume does. Fixed bodies never move and set none: the smallest body that
# moves does (slice-export and slice-info report the same figure).
volume_of_body = {}
fixed_body = set()
for row in BLOCKS:
    body = ('clump', row[3]) if len(rows_of_cluster.get(row[3], ())) >= 2 else ('block', row[0])
    volume_of_body[body] = volume_of_body.get(body, 0.0) + row[4]
    if row[1]:
        fixed_body.add(body)
moving = [v for body, v in volume_of_body.items() if body not in fixed_body]
smallest = min(moving) if moving else 1.0

# Cluster members too small for a DEM body (docs/dem-exports.md, "Small cluster members"): a
# clump moves as one, but each member is still a body whose contacts YADE computes, and a sliver
# far smaller than anything else the model integrates can make NaN. So a member of less than
# MIN_MEMBER_FRACTION of the smallest body that moves is no body: its mass and inertia go to the
# largest member of its cluster (that member's mass and inertia scaled by (its volume + theirs)
# / its volume), so the clump keeps its cluster's mass; its contacts are left out.
# merged_into: block -> that member.
MIN_MEMBER_FRACTION = 1e-2
merged_into = {}
mass_factor = {}   # receiving block -> the factor on its mass and inertia
for rows in rows_of_cluster.values():
    if len(rows) < 2:
        continue
    largest_row = max(rows, key=lambda row: row[4])
    for row in rows:
        if row is not largest_row and row[4] < MIN_MEMBER_FRACTION * smallest:
            merged_into[row[0]] = largest_row[0]
            mass_factor[largest_row[0]] = (mass_factor.get(largest_row[0], 1.0) +
                                           row[4] / largest_row[4])


def add_body(block, body):
    if block in mass_factor:
        body.state.mass *= mass_factor[block]
        body.state.inertia *= mass_factor[block]
    body_of_block[block] = O.bodies.append(body)


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
    # LAW 'mohr-coulomb': YADE's volumetric law gives the normal force only (friction angle 0:
    # its shear force is one for all contacts, docs/dem-exports.md), one material for all bodies;
    # the engine below (mohr_coulomb) adds each contact's shear and bond. 'volumetric': one
    # material per block with the block's friction angle, as YADE's law alone needs.
    shared_mat = None
    if LAW == 'mohr-coulomb':
        shared_mat = PolyhedraMat(young=YOUNG, poisson=POISSON, frictionAngle=0.0,
                                  density=DENSITY / SHRINK ** 3, label='rock')
        O.materials.append(shared_mat)
    for i, (block, fixed, phi, cluster, volume, centroid, vertices) in enumerate(BLOCKS):
        if block in merged_into:
            continue
        mat = shared_mat
        if mat is None:
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
        add_body(block, body)
        if (i + 1) % max(1, len(BLOCKS) // 10) == 0:
            progress('%d of %d bodies' % (i + 1, len(BLOCKS)))
else:
    from yade import potential_utils
    for i, (block, fixed, phi, cluster, volume, inradius, radius, centroid,
            planes) in enumerate(BLOCKS):
        if block in merged_into:
            continue
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
        add_body(block, body)
        if (i + 1) % max(1, len(BLOCKS) // 10) == 0:
            progress('%d of %d bodies' % (i + 1, len(BLOCKS)))

# Clusters become clumps; a clump with a fixed (boundary) member is fixed as a whole.
members_of_cluster = {}
fixed_cluster = set()
for row in BLOCKS:
    block, fixed, cluster = row[0], row[1], row[3]
    if cluster >= 0:
        if block in body_of_block:
            members_of_cluster.setdefault(cluster, []).append(body_of_block[block])
        if fixed:
            fixed_cluster.add(cluster)
clump_of_cluster = {}
for cluster in sorted(members_of_cluster):
    members = members_of_cluster[cluster]
    if len(members) < 2:
        if cluster in fixed_cluster:  # its one body took the mass of a fixed member
            O.bodies[members[0]].state.blockedDOFs = 'xyzXYZ'
            if SHAPE == 'polyhedra':
                O.bodies[members[0]].mask = FIXED_MASK
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
    ] + ([PyRunner(iterPeriod=1, command='rockslice_contact_law()', label='contact_law')]
         if LAW == 'mohr-coulomb' else []) + [
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

# LAW 'mohr-coulomb' (docs/dem-exports.md, "The contact law"): each contact keeps its own shear
# force and has its joint's strength. YADE's volumetric law (friction angle 0) gives the normal
# force Fn = kn x penetration volume along PolyhedraGeom's normal; this engine, run after it in
# every step, gives the shear force of each contact: Cundall's incremental spring, rotated with
# the contact, Fs <- Fs - ks A du (du: PolyhedraGeom.shearInc, A: the contact's area), limited by
# Fn tan(phi) + c A while the contact is bonded and Fn tan(phi) once it has slipped. A contact of
# the model (CONTACTS) starts bonded when its joint has cohesion or tension: the bond is a spring
# between the two blocks at the contact's centroid, normal kn A and shear ks A, that holds
# tension up to t A (if t > 0) and shear up to c A + Fn tan(phi) (if c > 0), and breaks for good
# past either; while it holds, a bond with cohesion carries the contact's shear. kn, ks: the
# volumetric law's (YOUNG / 2, POISSON x YOUNG / 2 per unit area and displacement).
contact_of_pair = {}   # (body id1, body id2), id1 < id2 -> (tan phi, cohesion, tension, area)
shear_of_pair = {}     # the shear force on body id2 of each touching contact (on id1: minus it)
bond_of_pair = {}      # the bonds that hold: [id1, id2, point in id1, point in id2, normal in id1]
if SHAPE == 'polyhedra' and LAW == 'mohr-coulomb':
    KN = YOUNG / 2.0
    KS = POISSON * YOUNG / 2.0
    # The model starts with no stress: gravity comes on at once, and a bond loaded at once swings
    # to about twice its static load. So bonds cannot break for the first BOND_SETTLE seconds,
    # ten periods sqrt(m / k) x 2 pi of the largest body that moves (NewtonIntegrator's damping
    # takes the swing out by then); past it, a bond breaks as soon as its load passes its
    # strength.
    largest = max(moving) if moving else 1.0
    BOND_SETTLE = 10 * 2 * math.pi * math.sqrt(DENSITY * largest ** (1.0 / 3) / KN)
    # A contact CONTACTS does not list (made later as blocks move, or in a 2-D section, which has
    # no CONTACTS) has the smaller of its two blocks' friction angles (BLOCKS), no cohesion, no
    # tension.
    tan_of_body = {body_of_block[row[0]]: math.tan(math.radians(row[2])) for row in BLOCKS
                   if row[0] in body_of_block}

    def _local(body, x):
        st = O.bodies[body].state
        return st.ori.conjugate() * (x - st.pos)
    for (a, b, phi, cohesion, tension, area, centroid, normal) in CONTACTS:
        if a not in body_of_block or b not in body_of_block:
            continue
        ia, ib = body_of_block[a], body_of_block[b]
        if O.bodies[ia].isClumpMember and O.bodies[ia].clumpId == O.bodies[ib].clumpId:
            continue  # one rigid body
        n = Vector3(normal)
        if ia > ib:
            ia, ib, n = ib, ia, -n
        contact_of_pair[(ia, ib)] = (math.tan(math.radians(phi)), cohesion, tension, area)
        if (cohesion > 0 or tension > 0) and not (O.bodies[ia].state.blockedDOFs == 'xyzXYZ' and
                                                    O.bodies[ib].state.blockedDOFs == 'xyzXYZ'):
            x = Vector3(centroid)
            bond_of_pair[(ia, ib)] = [ia, ib, _local(ia, x), _local(ib, x),
                                      O.bodies[ia].state.ori.conjugate() * n]


def _typical_area(i1, i2):
    # A contact the model does not list: the smaller body's V^(2/3) stands for its area.
    return min(O.bodies[i].shape.GetVolume() for i in (i1, i2)) ** (2.0 / 3)


def mohr_coulomb():
    forces = O.forces
    bodies = O.bodies
    touching = {}  # the touching contacts' normal force (YADE's volumetric law's)
    for I in O.interactions:
        g = I.geom
        key = (I.id1, I.id2)
        if not (g.equivalentPenetrationDepth > 1e-18 and g.penetrationVolume > 0):
            continue
        fn = touching[key] = I.phys.normalForce.norm()
        if key in bond_of_pair and contact_of_pair[key][1] > 0:
            continue  # a bond with cohesion carries the shear (below)
        props = contact_of_pair.get(key)
        if props is None:
            props = contact_of_pair[key] = (min(tan_of_body[key[0]], tan_of_body[key[1]]), 0.0,
                                            0.0, _typical_area(*key))
        n = g.normal
        fs = shear_of_pair.get(key)
        if fs is None:
            fs = Vector3(0, 0, 0)
        else:  # rotate with the contact (PolyhedraGeom.rotate)
            fs = fs - fs.cross(g.orthonormal_axis)
            fs = fs - fs.cross(g.twist_axis)
            fs = fs - n.dot(fs) * n
        fs = fs - (KS * props[3]) * g.shearInc
        limit = fn * props[0]
        size = fs.norm()
        if size > limit:
            fs = fs * (limit / size)
        shear_of_pair[key] = fs
        cp = g.contactPoint
        forces.addF(I.id1, -fs)
        forces.addF(I.id2, fs)
        forces.addT(I.id1, (cp - bodies[I.id1].state.pos).cross(-fs))
        forces.addT(I.id2, (cp - bodies[I.id2].state.pos).cross(fs))
    for key in [k for k in shear_of_pair if k not in touching]:
        del shear_of_pair[key]  # apart: a new touch starts from no shear
    broken = []
    settled = O.time >= BOND_SETTLE
    for key, (i1, i2, p1, p2, n1) in bond_of_pair.items():
        s1, s2 = bodies[i1].state, bodies[i2].state
        x1 = s1.pos + s1.ori * p1
        x2 = s2.pos + s2.ori * p2
        n = s1.ori * n1
        d = x2 - x1                      # how far the bond's two ends have moved apart
        tan_phi, cohesion, tension, area = contact_of_pair[key]
        opening = d.dot(n)
        f = Vector3(0, 0, 0)             # the bond's force on body 2
        if opening > 0 and tension > 0:
            pull = KN * area * opening   # tension
            if settled and pull > tension * area:
                broken.append(key)
                continue
            f = -pull * n
        if cohesion > 0:
            compression = touching.get(key, 0.0)
            fs = -(KS * area) * (d - opening * n)
            if settled and fs.norm() > cohesion * area + compression * tan_phi:
                broken.append(key)
                continue
            f = f + fs
        xm = 0.5 * (x1 + x2)
        forces.addF(i1, -f)
        forces.addF(i2, f)
        forces.addT(i1, (xm - s1.pos).cross(-f))
        forces.addT(i2, (xm - s2.pos).cross(f))
    for key in broken:
        del bond_of_pair[key]  # for good: friction alone from now on


if SHAPE == 'polyhedra' and LAW == 'mohr-coulomb':
    # PyRunner runs its command in __main__'s namespace, which is not this program's when
    # rockslice.yade.build() runs it.
    import __main__
    __main__.rockslice_contact_law = mohr_coulomb

if STEPS > 0:
    # Step progress: 20 lines over the run. (The command runs in YADE's own namespace: it
    # imports what it uses.)
    O.engines = O.engines + [PyRunner(iterPeriod=max(1, STEPS // 20), command=(
        "import time; print('rockslice: step %d of " + str(STEPS) + " (%.0f s)' % (O.iter + 1, "
        "time.time() - " + repr(time.time()) + "), flush=True)"))]
    progress('running %d steps, dt = %.3g s' % (STEPS, O.dt))
    O.run(STEPS, True)
    progress('done')
