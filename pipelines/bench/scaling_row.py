"""One CSV row of scaling.sh / scaling-nonpersistent.sh from a slice-cut run.

/usr/bin/python3 scaling_row.py stats.json rss.txt INDEX PARAMETER
  stats.json: slice-cut --stats; rss.txt: /usr/bin/time -f %M (kB); INDEX: yes | no;
  PARAMETER: the spacing or density of the run.
Prints: index,parameter,blocks,joints,seconds_cut,seconds_prune,lps_solved,lps_skipped,peak_rss_mb
"""
import json
import sys

s = json.load(open(sys.argv[1]))
rss_mb = int(open(sys.argv[2]).read().split()[-1]) / 1024
print(f"{sys.argv[3]},{sys.argv[4]},{s['blocks']},{s['joints']},"
      f"{s['seconds_cut'] + s['seconds_finish']:.4f},{s['seconds_prune']:.4f},"
      f"{s['lps_solved']},{s['pairs_skipped']},{rss_mb:.1f}")
