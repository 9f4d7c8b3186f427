#!/usr/bin/env python3
"""tools/paired.py BASE_COMPARE_DIR [VARIANT_DIR ...]: pairs the cooperative missions of the
base, or every mission of the variant folders if given (any mode: an oracle variant runs
rover-only with the jumper grounded), with the base's rover-only missions by seed.
Prints successes, and over seeds both reached B: mean path, replans, route changes, and the
cooperative change (negative = cooperative shorter / fewer). PAIRED=-v lists every seed."""
import glob, json, os, sys

def missions(folder):
    out = {}
    for report in glob.glob(os.path.join(folder, '*', 'report.json')):
        r = json.load(open(report))
        m = r.get('mission')
        if not m:
            continue
        cfg = r.get('config', {})
        seed = cfg.get('world', {}).get('seed')
        k = cfg.get('world', {}).get('rocks', {}).get('golombek_k')
        out[(seed, m['mode'])] = dict(m, k=k, dir=os.path.dirname(report))
    return out

base = missions(sys.argv[1])
coop = {}
variants = sys.argv[2:]
for folder in (variants or [sys.argv[1]]):
    found = missions(folder)
    for (seed, mode), m in found.items():
        # A variant folder's cooperative mission wins over another mode of the same seed.
        if mode == 'cooperative' or (variants and (seed, 'cooperative') not in found):
            coop[seed] = m
ro = {s: m for (s, mode), m in base.items() if mode == 'rover-only'}
seeds = sorted(set(ro) & set(coop))
verbose = os.environ.get('PAIRED') == '-v'
print(f"seeds {len(seeds)}: cooperative reached B {sum(coop[s]['goal_reached'] for s in seeds)}, "
      f"rover-only {sum(ro[s]['goal_reached'] for s in seeds)}")
both = [s for s in seeds if coop[s]['goal_reached'] and ro[s]['goal_reached']]
def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs) if xs else float('nan')
if verbose:
    print("seed  k      RO ok path  repl rc | CO ok path  repl rc hops | FK    built")
    for s in seeds:
        a, b = ro[s], coop[s]
        print(f"{s:4} {a['k'] or 0:.3f}  {int(a['goal_reached'])} {a['executed_path_m']:5.1f} {a['replans']:4} {a['route_changes']:3} |"
              f"  {int(b['goal_reached'])} {b['executed_path_m']:5.1f} {b['replans']:4} {b['route_changes']:3} {b['jumper_hops']:3} |"
              f" {b.get('full_knowledge_path_m') or 0:5.1f} {b.get('built_map_path_m') or 0:5.1f}")
for key in ['executed_path_m', 'replans', 'route_changes', 'node_expansions']:
    a, b = mean(ro[s][key] for s in both), mean(coop[s][key] for s in both)
    print(f"{key:16} over {len(both)} seeds: rover-only {a:8.1f}, cooperative {b:8.1f}, change {100*(b/a-1):+.1f} %")
fk = mean(ro[s]['full_knowledge_path_m'] for s in both if ro[s].get('full_knowledge_path_m'))
print(f"full-knowledge path {fk:.1f} m: headroom vs rover-only {100*(1-fk/mean(ro[s]['executed_path_m'] for s in both)):.1f} %")
