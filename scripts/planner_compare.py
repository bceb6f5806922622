#!/usr/bin/env python3
"""Quiver's planner beside AGM's (agglplanner) on the same problems: a Markdown table.

Reads the problems AGM's planner was run on and its results (a directory laid out as
/work/agm-run: problems.tsv, runs/runs.jsonl; the corpus of public files they name), runs
`quiver plan --json --runs N` on each problem AGM planned, and prints one row per problem:
AGM's median wall time as shipped (it waits 5 s after its first plan) and in first-plan mode,
ours (median of N runs: reading the world, compiling the rules and the mission, searching and
decomposing), the ratio, the costs (AGM's final cost; ours after decomposition and as searched,
hierarchical steps at their declared cost, which is what AGM reports), and whether our plan
replayed through the grammar guard.

Nothing here is needed by the tests: the corpus stays outside the tree.

Usage: planner_compare.py [--quiver build/quiver] [--agm /work/agm-run]
                          [--corpus /work/corpus/repos] [--runs 3] [--only P001,P002]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ap = argparse.ArgumentParser()
ap.add_argument('--quiver', default=os.path.join(os.path.dirname(__file__), '..', 'build', 'quiver-plan'),
                help='quiver-plan (the planner commands alone: starts in ms) or quiver')
ap.add_argument('--agm', default='/work/agm-run')
ap.add_argument('--corpus', default='/work/corpus/repos')
ap.add_argument('--runs', type=int, default=3)
ap.add_argument('--only', default=None)
ap.add_argument('--max-time', type=float, default=120)
ap.add_argument('--json-out', default=None, help='also write every row as JSON lines here')
a = ap.parse_args()

problems = list(csv.DictReader(open(os.path.join(a.agm, 'problems.tsv')), delimiter='\t'))
if a.only:
    keep = set(a.only.split(','))
    problems = [p for p in problems if p['problem_id'] in keep]

# AGM's runs, per problem and mode.
runs = {}
jl = os.path.join(a.agm, 'runs', 'runs.jsonl')
if os.path.exists(jl):
    for line in open(jl):
        try:
            r = json.loads(line)
        except ValueError:
            continue
        runs.setdefault(r['problem_id'], {}).setdefault(r['mode'], []).append(r)


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def agm_summary(pid):
    modes = runs.get(pid, {})
    shipped = [r for r in modes.get('shipped', []) if r.get('status') == 'planned']
    first = [r for r in modes.get('first', []) if r.get('status') == 'planned']
    any_runs = modes.get('shipped', []) + modes.get('first', [])
    status = 'planned' if shipped or first else (any_runs[0].get('status', '?') if any_runs else None)
    cost = None
    for r in shipped + first:
        if r.get('cost_final'):
            cost = float(r['cost_final'])
            break
    return {
        'status': status,
        'shipped_s': median([float(r['wall_s']) for r in shipped if r.get('wall_s')]),
        'first_s': median([float(r['wall_s']) for r in first if r.get('wall_s')]),
        'first_solution_s': median([float(r['first_solution_since_t0']) for r in first
                                    if r.get('first_solution_since_t0')]),
        'cost': cost,
        'plan': (shipped + first)[0].get('plan', []) if shipped or first else [],
        'runs': len(shipped) + len(first),
    }


def target_file(path, tmp):
    if not path.endswith('.xml'):
        return path
    out = os.path.join(tmp, os.path.basename(path) + '.aggt')
    conv = os.path.join(a.agm, 'tools', 'xmltarget2aggt.py')
    with open(out, 'w') as f:
        subprocess.run([sys.executable, conv, path], stdout=f, check=True)
    return out


rows = []
with tempfile.TemporaryDirectory() as tmp:
    for p in problems:
        pid = p['problem_id']
        agm = agm_summary(pid)
        if agm['status'] is None:
            continue  # AGM has not run it (yet)
        d, w, t = (os.path.join(a.corpus, p[k]) for k in ('domain', 'world', 'target'))
        row = {'id': pid, 'domain': p['domain'], 'target': p['target'], 'agm': agm}
        try:
            tt = target_file(t, tmp)
            pre = [a.quiver] + (['--log-level', 'off'] if os.path.basename(a.quiver) == 'quiver' else [])
            base = pre + ['plan', d, w, tt, '--json', '--max-time', str(a.max_time), '-I', os.path.join(a.agm, 'aggl-root')]
            cmd = base + ['--runs', str(a.runs)]
            if agm['plan']:
                # AGM's plan, replayed with our reading of the rules: does it reach the mission?
                pf = os.path.join(tmp, pid + '.plan')
                with open(pf, 'w') as f:
                    f.write('\n'.join(agm['plan']) + '\n')
                cmd += ['--replay', pf]
            res = subprocess.run(cmd, capture_output=True, text=True, cwd=os.path.dirname(w), timeout=a.max_time * a.runs + 60)
            out = res.stdout.strip().splitlines()
            row['ours'] = json.loads(out[-1]) if out and out[-1].startswith('{') else {'outcome': 'error', 'why': (res.stderr or res.stdout).strip()[:200]}
            if row['ours'].get('outcome') == 'found':
                # End to end, as AGM's times are: a process per request, its plan verified.
                walls = []
                for _ in range(a.runs):
                    t0 = time.perf_counter()
                    subprocess.run(base, capture_output=True, cwd=os.path.dirname(w), timeout=a.max_time + 60)
                    walls.append(time.perf_counter() - t0)
                row['ours']['process_s'] = statistics.median(walls)
        except Exception as e:  # a problem our loaders refuse is reported, not hidden
            row['ours'] = {'outcome': 'error', 'why': str(e)[:200]}
        rows.append(row)
        print(pid, agm['status'], row['ours'].get('outcome'), row['ours'].get('time_s'), file=sys.stderr)

if a.json_out:
    with open(a.json_out, 'w') as f:
        for r in rows:
            f.write(json.dumps(r) + '\n')


def fmt(x, nd=3):
    if x is None:
        return '–'
    if isinstance(x, float):
        return ('%.' + str(nd) + 'f') % x if x < 100 else '%.0f' % x
    return str(x)


def short(path):
    parts = path.split('/')
    return parts[0].split('__')[-1] + ':' + '/'.join(parts[-2:])


print('| problem | domain | target | AGM shipped s | AGM first-plan s | ours s | ours, process s | speed-up (first-plan) | speed-up, process | cost AGM | cost ours | ours as searched | verified | AGM plan, our reading |')
print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
ratios, ratios_shipped, ratios_proc = [], [], []
worse_invalid = []


def c_higher(ours, agm):
    return (ours.get('outcome') == 'found' and agm['cost'] is not None and
            ours.get('search_cost', ours.get('cost')) > agm['cost'] + 1e-9)


both = better = equal = worse = 0
for r in rows:
    agm, ours = r['agm'], r['ours']
    t_ours = ours.get('time_s') if ours.get('outcome') == 'found' else None
    t_agm = agm['first_s'] or agm['shipped_s']
    ratio = t_agm / t_ours if t_agm and t_ours else None
    if ratio:
        ratios.append(ratio)
    if agm['shipped_s'] and t_ours:
        ratios_shipped.append(agm['shipped_s'] / t_ours)
    cost_ours = ours.get('cost') if ours.get('outcome') == 'found' else None
    if agm['cost'] is not None and cost_ours is not None:
        both += 1
        c = ours.get('search_cost', cost_ours)
        if c < agm['cost'] - 1e-9:
            better += 1
        elif c > agm['cost'] + 1e-9:
            worse += 1
        else:
            equal += 1
    status_ours = ours.get('outcome') if ours.get('outcome') != 'found' else None
    rp = ours.get('replay')
    agm_valid = '–' if not rp else ('reaches it' if rp.get('reaches_mission') else
                                     ('does not reach it' if rp.get('applies') else 'a step does not apply'))
    if rp and not rp.get('reaches_mission') and c_higher(ours, agm):
        worse_invalid.append(r['id'])
    t_proc = ours.get('process_s')
    ratio_proc = t_agm / t_proc if t_agm and t_proc else None
    if ratio_proc:
        ratios_proc.append(ratio_proc)
    print('| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |' % (
        r['id'], short(r['domain']), os.path.basename(r['target']),
        fmt(agm['shipped_s']) if agm['status'] == 'planned' else agm['status'],
        fmt(agm['first_s']),
        fmt(t_ours, 4) if t_ours else (status_ours + ': ' + ours.get('why', '')[:60]).replace('|', '/'),
        fmt(t_proc, 4), ('%.0fx' % ratio) if ratio else '–', ('%.0fx' % ratio_proc) if ratio_proc else '–',
        fmt(agm['cost'], 1), fmt(cost_ours, 1), fmt(ours.get('search_cost'), 1) if cost_ours is not None else '–',
        ('ok' if ours.get('verified') == 'ok' else (ours.get('verified') or '–'))[:40].replace('|', '/'), agm_valid))

print()
if ratios:
    print('Problems both planners solved: %d; speed-up over AGM first-plan mode: median %.0fx, min %.0fx, max %.0fx'
          % (len(ratios), statistics.median(ratios), min(ratios), max(ratios)))
if ratios_proc:
    print('End to end (a quiver-plan process per request, plan verified) over AGM first-plan: median %.0fx, min %.0fx'
          % (statistics.median(ratios_proc), min(ratios_proc)))
if ratios_shipped:
    print('Speed-up over AGM as shipped (waits 5 s after its first plan): median %.0fx, min %.0fx'
          % (statistics.median(ratios_shipped), min(ratios_shipped)))
print('Cost (ours as searched vs AGM final): %d lower, %d equal, %d higher, of %d' % (better, equal, worse, both))
if worse_invalid:
    print('Where ours costs more, AGM\'s plan does not reach the mission under Quiver\'s reading of the rules: %s'
          % ', '.join(worse_invalid))
