#!/usr/bin/env python3
"""Writes the three scenes of the paper's Fig. 23 (data/kim-*.toml): one joint pattern in the
manner of Kim et al. (2007), their Fig. 8, given as deterministic joints, as the paper did:
  kim-persistent.toml     every joint a line through the section (Fig. 23 a)
  kim-nonpersistent.toml  every joint its segment (Fig. 23 b)
  kim-min-size.toml       the segments, no block under 0.4 m inscribed diameter (Fig. 23 c)
The traces are drawn here once, with a fixed seed, and written out with 17 digits, so the
scenes are plain files that need nothing else: run  /usr/bin/python3 data/kim/make.py  to
write them again (the same bytes)."""
import math
import os
import random

WIDTH, HEIGHT = 20.0, 12.0
# (dip, dip direction, traces, trace length range [m]): three families, as in a bedded rock.
FAMILIES = [(15.0, 90, 18, (4.0, 12.0)), (70.0, 270, 22, (2.0, 6.0)), (55.0, 90, 16, (2.0, 5.0))]

def traces():
    rng = random.Random(2007)
    out = []
    for dip, dd, count, (lo, hi) in FAMILIES:
        d = math.radians(dip)
        s = 1 if dd == 90 else -1
        ux, uz = math.cos(d), -s * math.sin(d)  # along the line, in (x, z)
        for _ in range(count):
            cx, cz = rng.uniform(0, WIDTH), rng.uniform(0, HEIGHT)
            half = rng.uniform(lo, hi) / 2
            out.append((dip, dd, (cx, cz), (cx - half * ux, cz - half * uz),
                        (cx + half * ux, cz + half * uz)))
    return out

def scene(name, title, segments, min_size):
    lines = ['# %s' % title,
             '# Written by data/kim/make.py (do not edit: run it again).',
             '[scene]', 'name = "%s"' % name, 'dimension = 2', '',
             '[domain]', 'box = { min = [0, 0], max = [%g, %g] }' % (WIDTH, HEIGHT), '',
             '[options]', 'order = "as-given"']
    if min_size:
        lines.append('min_inscribed_diameter = 0.4')
    for dip, dd, c, a, b in traces():
        lines += ['', '[[joints]]', 'dip = %r' % dip, 'dip_direction = %d' % dd,
                  'point = [%r, %r]' % c]
        if segments:
            lines.append('segment = [[%r, %r], [%r, %r]]' % (a + b))
    return '\n'.join(lines) + '\n'

here = os.path.dirname(os.path.abspath(__file__))
for name, title, seg, size in [
        ('kim-persistent', 'Fig. 23 (a): the pattern with every joint persistent', False, False),
        ('kim-nonpersistent', 'Fig. 23 (b): the pattern with its joints as segments', True, False),
        ('kim-min-size', 'Fig. 23 (c): segments, minimum block size 0.4 m', True, True)]:
    with open(os.path.join(here, '..', name + '.toml'), 'w') as f:
        f.write(scene(name, title, seg, size))
