"""Plots results/yade-steps.csv (pipelines/bench/yade-steps.sh): seconds per step against bodies,
and the throughput in steps per second per 1,000 bodies, for each variant and thread count; with
results/yade-settle.csv, a third panel: seconds per step along the 1k box's settling run.
    /usr/bin/python3 pipelines/bench/yade-plot.py results/yade-steps.csv results/yade-steps.png \
        [results/yade-settle.csv]
"""
import os
import csv
import sys

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
settle = sys.argv[3] if len(sys.argv) > 3 and os.path.exists(sys.argv[3]) else ''
fig, axes = plt.subplots(1, 3 if settle else 2, figsize=(16 if settle else 11, 4.5))
ax1, ax2 = axes[0], axes[1]
styles = {'touching': ('tab:red', 'before (touching, fixed pairs)'),
          'export': ('tab:blue', 'now (1e-6 gap, no fixed pairs)'),
          'gap-only': ('tab:green', 'gap only'),
          'fixed-pairs': ('tab:orange', 'no fixed pairs only')}
for variant, (colour, label) in styles.items():
    for threads, marker, line in (('1', 'o', '-'), ('2', 's', '--')):
        pts = sorted((int(r['bodies']), float(r['cpu_s_per_step' if threads == '1' else
                                                  'wall_s_per_step']), r['scene'])
                     for r in rows if r['variant'] == variant and r['threads'] == threads and
                     r['scene'].startswith('yade-box'))
        if not pts:
            continue
        x = [p[0] for p in pts]
        y = [p[1] for p in pts]
        name = '%s, %s' % (label, '1 core (CPU s)' if threads == '1' else '-j2 (wall s)')
        ax1.loglog(x, y, marker=marker, linestyle=line, color=colour, label=name)
        ax2.semilogx(x, [n / 1000 / t for n, t in zip(x, y)], marker=marker, linestyle=line,
                     color=colour, label=name)
    for r in rows:  # the 1,000 cubes of data/cube-3sets.toml, one core
        if r['scene'] == 'cube-3sets' and r['variant'] == variant and r['threads'] == '1':
            t = float(r['cpu_s_per_step'])
            ax1.plot(int(r['bodies']), t, marker='*', markersize=12, color=colour, linestyle='')
            ax2.plot(int(r['bodies']), int(r['bodies']) / 1000 / t, marker='*', markersize=12,
                     color=colour, linestyle='')
ax1.set_xlabel('bodies')
ax1.set_ylabel('seconds per step')
ax1.set_title('yade-box (lines); cube-3sets (stars, 1 core)')
ax1.grid(True, which='both', alpha=0.3)
ax2.set_xlabel('bodies')
ax2.set_ylabel('steps per second per 1,000 bodies')
ax2.set_ylim(bottom=0)
ax2.grid(True, which='both', alpha=0.3)
ax2.legend(fontsize=7)
if settle:
    ax3 = axes[2]
    srows = list(csv.DictReader(open(settle)))
    for variant, (colour, label) in styles.items():
        pts = [(int(r['iteration']), float(r['cpu_s_per_step']), int(r['real']))
               for r in srows if r['variant'] == variant]
        if pts:
            ax3.plot([p[0] for p in pts], [p[1] for p in pts], marker='o', color=colour,
                     label=label + ', CPU s per step')
    ax3b = ax3.twinx()
    for variant, (colour, label) in styles.items():
        pts = [(int(r['iteration']), int(r['real'])) for r in srows if r['variant'] == variant]
        if pts:
            ax3b.plot([p[0] for p in pts], [p[1] for p in pts], linestyle=':', color=colour,
                      label=label + ', real contacts')
    ax3.set_xlabel('step')
    ax3.set_ylabel('CPU seconds per step (1 core)')
    ax3b.set_ylabel('real contacts (dotted)')
    ax3.set_ylim(bottom=0)
    ax3b.set_ylim(bottom=0)
    ax3.set_title('%s settling (%s bodies)' % (srows[0]['scene'] if srows else '',
                                              next((r['bodies'] for r in rows if srows and
                                                    r['scene'] == srows[0]['scene']), '?')))
    ax3.grid(True, alpha=0.3)
    ax3.legend(fontsize=7, loc='lower right')
machine = rows[0]['machine'] if rows else ''
fig.suptitle('YADE 2023.02a Polyhedra, exported by slice-export --format yade (%s)' % machine,
             fontsize=9)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
