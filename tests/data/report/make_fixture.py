#!/usr/bin/env python3
"""Build the report test fixture tests/data/report/run/ (a small run directory in the agreed
formats, docs/report.md#run-directory) from real outputs:

    make_fixture.py TABLES_DIR OPTIMISE_DIR OUT_DIR

TABLES_DIR: `manta tables --campaign examples/ranger2000/campaign.yaml --out ...`;
OPTIMISE_DIR: `manta optimise --manoeuvre examples/ranger2000/manoeuvres/immelmann.yaml --out ...`
(trajectory.csv with *_deg columns is converted to the trajectory CSV of docs/formats.md).
The tables are cut to two Mach numbers and two sideslips, the controls to three deflections; the
replay is synthetic (table plus a lag and a spike where the elevator moves fast), so the report
has flagged intervals to show. Standard library only."""
import csv, json, math, os, shutil, sys

tables_dir, opt_dir, out = sys.argv[1:4]
root = os.path.dirname(os.path.abspath(__file__))
repo = os.path.abspath(os.path.join(root, '..', '..', '..'))
shutil.rmtree(out, ignore_errors=True)
for d in ('tables', 'manoeuvres/immelmann', 'replay/immelmann'):
    os.makedirs(os.path.join(out, d))
shutil.copy(os.path.join(repo, 'examples/ranger2000/aircraft.yaml'), os.path.join(out, 'aircraft.yaml'))

# ---- tables
machs, betas, deltas_keep = {'0.2', '0.5'}, {'0', '8'}, None
with open(os.path.join(tables_dir, 'tables.csv')) as f:
    lines = f.read().splitlines()
rows = [lines[0], lines[1]]
deltas = {}
for ln in lines[2:]:
    c = ln.split(',')
    if c[0] != 'static':
        deltas.setdefault(c[0], set()).add(float(c[4]))
for ln in lines[2:]:
    c = ln.split(',')
    if c[2] not in machs:
        continue
    if c[0] == 'static' and c[3] in betas:
        rows.append(ln)
    elif c[0] != 'static':
        d = float(c[4])
        if d in (min(deltas[c[0]]), 0.0, max(deltas[c[0]])):
            rows.append(ln)
open(os.path.join(out, 'tables/tables.csv'), 'w').write('\n'.join(rows) + '\n')
with open(os.path.join(tables_dir, 'samples.csv')) as f:
    r = list(csv.reader(f))
keep = [r[0]]
for row in r[1:]:
    d = dict(zip(r[0], row))
    if d['scenario'] == 'static' and d['mach'] in machs or d['scenario'] != 'static' and len(keep) < 40:
        keep.append(row)
# One failed sample with a quoted, comma-holding error text (the reader must cope).
failed = dict(zip(r[0], r[1]))
failed.update({'id': '9999', 'status': 'failed', 'error': 'solver diverged, "residual" 1e+3'})
for k in ('CL', 'CD', 'CY', 'Cl', 'Cm', 'Cn', 'CX', 'CY_body', 'CZ', 'CD_induced', 'CD_profile'):
    failed[k] = ''
keep.append([failed[k] for k in r[0]])
with open(os.path.join(out, 'tables/samples.csv'), 'w', newline='') as f:
    csv.writer(f, lineterminator='\n').writerows(keep)
shutil.copy(os.path.join(tables_dir, 'dynamic.csv'), os.path.join(out, 'tables/dynamic.csv'))
s = json.load(open(os.path.join(tables_dir, 'summary.json')))
s['store'] = 'samples.sqlite'
json.dump(s, open(os.path.join(out, 'tables/summary.json'), 'w'), indent=2, sort_keys=True)

# ---- manoeuvre: the trajectory CSV of docs/formats.md
deg = math.pi / 180
with open(os.path.join(opt_dir, 'trajectory.csv')) as f:
    t = list(csv.DictReader(f))
cols = ['t', 'x', 'y', 'z', 'phi', 'theta', 'psi', 'V', 'alpha', 'beta', 'p', 'q', 'r', 'elevator',
        'aileron', 'rudder', 'throttle', 'phase', 'mach', 'altitude', 'nz', 'CL', 'CD', 'CY', 'Cl',
        'Cm', 'Cn']
def convert(d):
    return [float(d['t_s']), float(d['x_m']), float(d['y_m']), -float(d['altitude_m']),
            float(d['bank_deg']) * deg, float(d['pitch_deg']) * deg, float(d['heading_deg']) * deg,
            float(d['V_m_s']), float(d['alpha_deg']) * deg, float(d['beta_deg']) * deg,
            float(d['p_deg_s']) * deg, float(d['q_deg_s']) * deg, float(d['r_deg_s']) * deg,
            float(d['elevator_deg']) * deg, float(d['aileron_deg']) * deg,
            float(d['rudder_deg']) * deg, float(d['throttle']), 0, float(d['mach']),
            float(d['altitude_m']), float(d['load_factor']), float(d['CL']), float(d['CD']),
            float(d['CY']), float(d['Cl']), float(d['Cm']), float(d['Cn'])]
nodes = [convert(d) for d in t]
# Unwrap psi (the agreed format keeps it continuous).
for i in range(1, len(nodes)):
    while nodes[i][6] - nodes[i - 1][6] > math.pi: nodes[i][6] -= 2 * math.pi
    while nodes[i][6] - nodes[i - 1][6] < -math.pi: nodes[i][6] += 2 * math.pi
tf = nodes[-1][0]
for n in nodes:
    n[17] = 0 if n[0] < 0.45 * tf else 1
meta = ['# manoeuvre: immelmann', '# aircraft: aircraft.yaml', '# mass_case: immelmann',
        '# phases: pull-up,roll-out', '# nodes: %d' % len(nodes), '# final_time: %.10g' % tf]
def write(path, rows):
    with open(path, 'w') as f:
        f.write('\n'.join(meta) + '\n' + ','.join(cols) + '\n')
        for row in rows:
            f.write(','.join('%.7g' % v for v in row) + '\n')
write(os.path.join(out, 'manoeuvres/immelmann/trajectory.csv'), nodes)
# A 0.25 s grid joined with the node times, linear between nodes (a stand-in for the
# solution's Lagrange interpolant: the curve passes through every node).
step = 0.25
times = sorted(set([round(i * step, 10) for i in range(int(tf / step) + 1)] + [n[0] for n in nodes]))
dense, k = [], 0
for tt in times:
    while k + 1 < len(nodes) - 1 and nodes[k + 1][0] < tt: k += 1
    a, b = nodes[k], nodes[k + 1]
    w = (tt - a[0]) / (b[0] - a[0])
    row = [a[j] + w * (b[j] - a[j]) for j in range(len(cols))]
    row[0] = tt
    row[17] = a[17]
    dense.append(row)
write(os.path.join(out, 'manoeuvres/immelmann/trajectory_dense.csv'), dense)
s = json.load(open(os.path.join(opt_dir, 'summary.json')))
json.dump(s, open(os.path.join(out, 'manoeuvres/immelmann/summary.json'), 'w'), indent=2, sort_keys=True)

# ---- replay (synthetic; the format of docs/formats.md, replay output directory)
names = ['CL', 'CD', 'CY', 'Cl', 'Cm', 'Cn']
tol = {'CL': 0.02, 'CD': 0.002, 'CY': 0.005, 'Cl': 0.002, 'Cm': 0.01, 'Cn': 0.002}
ci = {c: cols.index(c) for c in cols}
hdr = ['t', 'phase', 'alpha', 'beta', 'V', 'mach', 'p', 'q', 'r', 'elevator', 'aileron', 'rudder',
       'elevator_rate', 'aileron_rate', 'rudder_rate']
for c in names:
    hdr += [c + '_replay', c + '_table', c + '_diff']
hdr.append('flag')
rep = []
grid = [d for d in dense if abs(d[0] / step - round(d[0] / step)) < 1e-9 or d is dense[-1]]
for i, d in enumerate(grid):
    prev = grid[max(i - 1, 0)]
    nxt = grid[min(i + 1, len(grid) - 1)]
    dt = max(nxt[0] - prev[0], 1e-9)
    rates = [(nxt[ci[c]] - prev[ci[c]]) / dt for c in ('elevator', 'aileron', 'rudder')]
    row = [d[0], d[17], d[ci['alpha']], d[ci['beta']], d[ci['V']], d[ci['mach']], d[ci['p']],
           d[ci['q']], d[ci['r']], d[ci['elevator']], d[ci['aileron']], d[ci['rudder']]] + rates
    flag = 0
    for c in names:
        table = d[ci[c]]
        # A lag of the lift and moment behind fast elevator motion (an unsteady effect).
        extra = {'CL': 0.004, 'CD': 0.0004, 'CY': 0.0, 'Cl': 0.0, 'Cm': -0.003, 'Cn': 0.0}[c] * rates[0] / deg
        extra += 0.2 * tol[c] * math.sin(0.7 * d[0])
        rpl = table + extra
        if abs(extra) > tol[c]: flag = 1
        row += [rpl, table, rpl - table]
    row.append(flag)
    rep.append(row)
with open(os.path.join(out, 'replay/immelmann/comparison.csv'), 'w') as f:
    f.write(','.join(hdr) + '\n')
    for row in rep:
        f.write(','.join('%.7g' % v for v in row) + '\n')
def stats(rows):
    out = {}
    for c in names:
        j = hdr.index(c + '_diff')
        dif = [r[j] for r in rows]
        k = max(range(len(dif)), key=lambda i: abs(dif[i]))
        out[c] = {'rms': math.sqrt(sum(x * x for x in dif) / len(dif)), 'max_abs': abs(dif[k]),
                  't_max': rows[k][0],
                  'mean_replay': sum(r[hdr.index(c + '_replay')] for r in rows) / len(rows),
                  'mean_table': sum(r[hdr.index(c + '_table')] for r in rows) / len(rows)}
    return out
flags, i = [], 0
while i < len(rep):
    if rep[i][-1]:
        j = i
        while j + 1 < len(rep) and rep[j + 1][-1]: j += 1
        seg = rep[i:j + 1]
        over = [c for c in names if max(abs(r[hdr.index(c + '_diff')]) for r in seg) > tol[c]]
        flags.append({'t_start': rep[i][0], 't_end': rep[j][0], 'coefficients': over,
                      'max_diff': {c: max(abs(r[hdr.index(c + '_diff')]) for r in seg) for c in over},
                      'state': {'alpha_max': max(abs(r[2]) for r in seg),
                                'rate_max': max(max(abs(r[6]), abs(r[7]), abs(r[8])) for r in seg),
                                'control_rate_max': max(max(abs(r[12]), abs(r[13]), abs(r[14])) for r in seg),
                                'mach_max': max(r[5] for r in seg)},
                      'reasons': ['fast elevator motion'] + (['high angle of attack'] if max(abs(r[2]) for r in seg) > 10 * deg else [])})
        i = j + 1
    else:
        i += 1
phases = []
for p, name in enumerate(['pull-up', 'roll-out']):
    seg = [r for r in rep if r[1] == p]
    st = stats(seg)
    phases.append({'name': name, 't_start': seg[0][0], 't_end': seg[-1][0],
                   'coefficients': {c: {'rms': st[c]['rms'], 'max_abs': st[c]['max_abs']} for c in names}})
summary = {'source': 'vlm', 'trajectory': 'manoeuvres/immelmann/trajectory_dense.csv',
           'manoeuvre': 'immelmann', 'dt': 0.25, 'steps': len(rep), 'wall_time_s': 12.5,
           'cpu_time_s': 24.1, 'resumed_from_step': None, 'tolerances': tol,
           'coefficients': stats(rep), 'phases': phases, 'flags': flags}
json.dump(summary, open(os.path.join(out, 'replay/immelmann/summary.json'), 'w'), indent=2)

run = {'manta_version': '0.1.0', 'command': 'manta demo --out RUN_DIR', 'started': '2026-11-22T19:00:00Z',
       'settings': {'fidelity': 'vlm', 'manoeuvres': ['immelmann'], 'jobs': 2,
                    'campaign': 'examples/ranger2000/campaign.yaml'},
       'timings_s': {'tables': 5.8, 'optimise': {'immelmann': 178.7}, 'replay': {'immelmann': 12.5},
                     'report': 0.4},
       'aircraft': 'aircraft.yaml'}
json.dump(run, open(os.path.join(out, 'run.json'), 'w'), indent=2)
