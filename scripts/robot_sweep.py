#!/usr/bin/env python3
"""Competitors-only sweep over the robot task's open settings (issue 21; docs/paper-notes.md §8.5).

Runs the three paper competitors (no EA-MADM) on the default scenario with the given settings
changed, with the release xtask (`cargo build -p xtask --release` first), and prints the
final-window reach share and the greedy seeds reaching per competitor.

usage: scripts/robot_sweep.py NAME [episodes=300] [seeds=20] [base_seed=0] [control_period=0.2]
       [step_cap=500] [reach_radius=0.05] [arena=fig12|no5|gate20|gate20no5] [state.FIELD=V] ...
Outputs go to target/sweep/NAME/; one line per call is appended to target/sweep/results.txt."""
import csv, os, re, subprocess, sys, collections, time, resource
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
binary = os.environ.get('XTASK', root + '/target/release/xtask')
name = sys.argv[1]
kv = dict(a.split('=', 1) for a in sys.argv[2:])
episodes = kv.pop('episodes', '300')
seeds = kv.pop('seeds', '20')
base_seed = kv.pop('base_seed', '0')
base = open(root + '/crates/wmr-model/scenarios/fig12.toml').read()
scen = base
top = {k: kv.pop(k) for k in list(kv) if k in ('control_period', 'step_cap')}
for k, v in top.items():
    scen = re.sub(rf'^{k} = .*$', f'{k} = {v}', scen, flags=re.M)
if 'reach_radius' in kv:
    scen = re.sub(r'^reach_radius = .*$', f"reach_radius = {kv.pop('reach_radius')}", scen, flags=re.M)
arena = kv.pop('arena', 'fig12')
blocks = scen.split('[[obstacles]]')
if arena == 'no5':
    scen = '[[obstacles]]'.join(blocks[:5])
elif arena == 'gate20':
    scen = scen.replace('y = 0.37\nwidth = 0.08\nheight = 0.14', 'y = 0.34\nwidth = 0.08\nheight = 0.14').replace('y = 0.64\nwidth = 0.08\nheight = 0.12', 'y = 0.67\nwidth = 0.08\nheight = 0.12')
elif arena == 'gate20no5':
    scen = '[[obstacles]]'.join(blocks[:5])
    scen = scen.replace('y = 0.37\nwidth = 0.08\nheight = 0.14', 'y = 0.34\nwidth = 0.08\nheight = 0.14').replace('y = 0.64\nwidth = 0.08\nheight = 0.12', 'y = 0.67\nwidth = 0.08\nheight = 0.12')
sections = collections.defaultdict(list)
for k, v in list(kv.items()):
    sec, field = k.split('.', 1)
    sections[sec].append(f'{field} = {v}')
    kv.pop(k)
for sec, lines in sections.items():
    scen += f'\n[{sec}]\n' + '\n'.join(lines) + '\n'
d = f'{root}/target/sweep/{name}'
os.makedirs(d, exist_ok=True)
open(f'{d}/scenario.toml', 'w').write(scen)
cfg = open(root + '/crates/eamadm/configs/robot.toml').read()
cfg = cfg.split('# The proposed method')[0]
# the preset's own choices of the open settings are what the sweep varies: start from the scenario
cfg = re.sub(r'^(control_period|step_cap|reach_radius|distance_bins) = .*\n', '', cfg, flags=re.M)
cfg = re.sub(r'^episodes = .*$', f'episodes = {episodes}', cfg, count=1, flags=re.M)
cfg = cfg.replace('base_seed = 0', f'base_seed = {base_seed}')
cfg = cfg.replace('scenario = "default"', f'scenario = "{d}/scenario.toml"')
cfg += '''
[[methods]]
label = "epsilon-greedy"
kind = "epsilon_greedy"
epsilon = { constant = 0.1 }

[[methods]]
label = "epsilon-decreasing"
kind = "epsilon_greedy"
epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } }

[[methods]]
label = "softmax"
kind = "softmax"
temperature = { exponential = { start = 0.1, factor = 0.95, floor = 0.01 } }
'''
open(f'{d}/config.toml', 'w').write(cfg)
t0 = time.time(); r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
p = subprocess.run([binary, 'reproduce-paper', '--config', f'{d}/config.toml', '--out', f'{d}/out', '--seeds', seeds], capture_output=True, text=True)
r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
if p.returncode:
    print(p.stderr[-2000:]); sys.exit(1)
rows = list(csv.DictReader(open(f'{d}/out/final-scores.csv')))
out = [name, ' '.join(sys.argv[2:]), f'{r1.ru_utime - r0.ru_utime:.1f}s']
for m in ('epsilon-greedy', 'epsilon-decreasing', 'softmax'):
    rs = [r for r in rows if r['method'] == m]
    sr = sum(float(r['success_rate']) for r in rs) / len(rs)
    g = sum(r['greedy_reached'] == 'true' for r in rs)
    out.append(f'{m}: {sr*100:.0f}% {g}/{len(rs)}')
line = ' | '.join(out)
print(line)
open(f'{root}/target/sweep/results.txt', 'a').write(line + '\n')
