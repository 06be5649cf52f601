"""`voidcross sim`: run, soak and benchmark the swarm simulator (swarm_sim, cm and s)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from swarm_sim.errors import InputError
from voidcross.output import (
    MAX_ROBOTS,
    MAX_RUNS,
    MAX_SIM_TIME_S,
    MAX_WORKERS,
    check_float,
    check_int,
    check_seed,
    emit,
    out_dir,
    out_file,
    parse_set,
    progress,
)

#: sim bench: the largest swarm and the most steps one call times (user terms: memory, minutes)
MAX_BENCH_ROBOTS = 1_000_000
MAX_BENCH_STEPS = 1_000_000

RUN_EPILOG = """examples:
  voidcross sim run --preset case-d --robots 9 --void-width 2 --seed 1 --json   (the derived line spans 2)
  voidcross sim run --preset case-c --robots 8 --void-width 3 --limits thesis   (retreats: 3w - 1)
  voidcross sim run --preset case-a --robots 8 --void-width 2 --limits thesis --video run.mp4
  voidcross sim run --preset case-d --robots 9 --void-width 3 --limits thesis --snapshots snaps --out results/sim
  voidcross sim run --preset large-void --robots 70 --void-width 8 --limits thesis   (line -> two lines)
  voidcross sim run --preset large-void-8 --void-width 6 --robots 416   (the derived widest void: line -> 4x2 -> 6x3 -> 8x4 arches)
  voidcross sim run --preset large-void-15 --robots 200 --void-width 15 --limits thesis   (tapering arch-15, ~4 s compiled)
  voidcross sim run --preset large-void-30 --robots 470 --void-width 30 --limits thesis   (tapering arch-30, ~15 s compiled)
  voidcross sim run --preset large-void-15 --limits thesis --snapshots snaps --frame-every 200   (side view: both feet)
  voidcross sim run --preset my-arena.toml --robots 20 --void-width 4 --set arena_w_cm=800 --debug
presets: case-a, case-b, case-c, case-d, large-void, large-void-8, large-void-15, large-void-30
(swarm_sim/presets/*.toml) or a TOML path.
--limits: derived (structure_fem's packaged limits.json, the default), thesis, or a limits.json path.
Times in the result are simulated seconds: Ts initial exploration, Ta assembly and crossing,
To target search, Td retreat and disassembly, Tb wander after a retreat, Tt total.
"""

SOAK_EPILOG = """examples:
  voidcross sim soak --runs 200 --json
  voidcross sim soak --runs 10000 --workers 2 --json --journal soak.jsonl   (resumable)
  voidcross sim soak --runs 500 --limits thesis --seed 7
Each run draws a preset (every shipped one), limits (derived and thesis), swarm size around
the rule minimum, void width, arena, obstacles, structure and seed, and runs to its end
(crossed or retreated) with every invariant checked after every step. Timeouts (the time
limit is only a guard), violations, lost robots and crashes are counted apart, each
reported with the draw that caused it. Exit 1 if any was found.
"""

BENCH_EPILOG = """examples:
  voidcross sim bench --robots 10000 --steps 500 --json
  voidcross sim bench --robots 1000 --steps 200 --no-scaling
  voidcross sim bench --workload thesis --seeds 3 --json
Default workload: exploration only (random walk, wall and robot avoidance), arena sized so the robots cover 5 %
of the floor. robot_steps_per_s is measured in CPU time of this process (the machine may be
shared); scaling_exponent fits cost per step against N over 1,000..100,000 robots.
--workload thesis: the thesis's bridge runs (cases A-D at their boundaries, a retreat, both
limit sets) to their end; CPU s per run, us per step and the ratio of its robot-steps/s to the
exploration rate measured in the same call.
"""


def _write_json_atomic(path: Path, payload: dict) -> None:
    from cubot_cad.atomic import write_json

    write_json(path, payload, allow_nan=False)


def _under(out: Path, name: str) -> Path:
    p = Path(name)
    return p if p.is_absolute() else out / p


def _rendering(desc: str, count: int, noun: str, target: Path, work):
    """``work(bar)`` with progress on stderr (a bar on a terminal; off one, a first line and
    then a plain line every half minute), ended by one line saying how long it took."""
    import sys
    import time

    if not sys.stderr.isatty():
        print(f"{desc}: {count} {noun} -> {target}", file=sys.stderr, flush=True)
    t0 = time.monotonic()
    out = work(lambda it, n: progress(it, desc, n))
    dt = time.monotonic() - t0
    rate = f", {count / dt:.0f} {noun}/s" if dt > 0 and count > 1 else ""
    print(f"{desc}: {count} {noun} in {dt:.1f} s{rate} -> {target}", file=sys.stderr, flush=True)
    return out


def run(args: argparse.Namespace) -> int:
    from swarm_sim.runner import resolve_engine, resolve_params, simulate

    engine = resolve_engine(args.engine)
    check_int(args.robots, "--robots", 1, MAX_ROBOTS, "robots in the swarm")
    check_int(args.void_width, "--void-width", 1, None, "robot widths")
    if args.video and Path(args.video).suffix.lower() not in (".mp4", ".gif"):
        raise InputError(f"--video {args.video}: use a .mp4 or .gif file name")
    check_seed(args.seed)
    check_float(args.max_time, "--max-time", 0.0, MAX_SIM_TIME_S, what="simulated seconds")
    if not (math.isfinite(args.frame_every) and args.frame_every > 0):
        raise InputError(f"--frame-every {args.frame_every}: must be a positive number of simulated seconds")
    overrides = parse_set(args.set)
    if args.faults is not None:
        from swarm_sim.faults import parse_faults

        spec = parse_faults(args.faults)
        overrides["faults"] = "" if spec.empty else spec.describe()
    from swarm_sim.params import load_preset

    base = load_preset(args.preset)
    robots = args.robots if args.robots is not None else base.robots
    width = args.void_width if args.void_width is not None else base.void_width
    p = resolve_params(args.preset, robots, width, args.limits, args.max_time, **overrides)
    if args.frame_every < p.dt_s:
        raise InputError(f"--frame-every {args.frame_every}: shorter than one step ({p.dt_s:g} s)")
    if args.frame_every > p.max_time_s:
        raise InputError(f"--frame-every {args.frame_every:g}: longer than the run's time limit "
                         f"({p.max_time_s:g} simulated s): no frame after the first")
    # every output path is checked before the run (one error line, exit 2, nothing computed)
    base = Path(args.out or "results/sim")
    video = _under(base, args.video) if args.video else None
    snaps = _under(base, args.snapshots) if args.snapshots else None
    if args.out is not None:
        out_dir(base, "--out", create=False)
    if video is not None:
        out_file(video, "--video")
    if snaps is not None:
        out_dir(snaps, "--snapshots", create=False)
    recorder = None
    if args.video or args.snapshots:
        from swarm_sim.render import Recorder

        recorder = Recorder(every_s=args.frame_every)
    state, res = simulate(p, args.seed, check=args.debug, on_step=recorder, engine=engine)
    payload = res.to_dict(events=args.events)
    payload["limits_rule"] = {"ground_ratio": p.ground_ratio, "ground_margin": p.ground_margin,
                              "line_max_span_widths": p.max_span_widths}
    files = []
    if video is not None or snaps is not None or args.out is not None:
        if video is not None:
            from swarm_sim.render import write_video

            files.append(str(_rendering("rendering video", len(recorder.frames), "frames", video,
                                        lambda bar: write_video(recorder.frames, p, video, progress=bar))))
        if snaps is not None:
            from swarm_sim.render import snapshot_frames, write_snapshots

            n = len(snapshot_frames(recorder.frames, 6))
            files += [str(f) for f in _rendering("snapshots", n, "snapshots", snaps,
                                                 lambda bar: write_snapshots(recorder.frames, p, snaps, progress=bar))]
        if args.out is not None:
            target = base / f"run-{p.preset}-N{p.robots}-w{p.void_width}-s{args.seed}.json"
            _write_json_atomic(target, res.to_dict(events=True))
            files.append(str(target))
    payload["files"] = files
    t = res.times
    why = {"retreated-no-robots": "too few robots for this void",
           "retreated-span": "the far ledge is beyond the widest structure's span",
           "retreated-stalled": "no free robot could reach the dock",
           "retreated-blocked": "the rear dock point is off the arena",
           "retreated-no-room": "no room for the tapering arch's feet"}.get(res.end_reason or "", "")
    outcome = "SUCCESS: crossed and found the target" if res.success else (
        f"RETREATED ({res.end_reason}): {why}; all back on the initial side" if res.retreated
        else "STRANDED: every robot that could still finish the task has failed" if res.end_reason == "stranded"
        else "TIMEOUT: still running at --max-time")
    fmt = lambda v: "-" if v is None else f"{v:.2f}"  # noqa: E731
    human = (f"{p.preset} N={p.robots} void={p.void_width} widths seed={args.seed} limits={p.limits_source} "
             f"(rule n_p >= {p.ground_ratio:g} n_g + {p.ground_margin}, min robots {p.min_robots_rule or 'n/a'} "
             f"by the rule, {p.record_min_robots or 'n/a'} by the record)\n"
             f"{outcome}; robots lost {res.robots_lost}; delivered {res.robots_delivered} of {p.robots}, "
             f"{res.robots_on_initial_side} on the initial side\n"
             f"seed robot {res.seed_robot} at {res.seed_position}, target found by {res.target_finder}\n"
             f"Ts {fmt(t['Ts'])}  Ta {fmt(t['Ta'])}  To {fmt(t['To'])}  Td {fmt(t['Td'])}  "
             f"Tb {fmt(t['Tb'])}  Tt {fmt(t['Tt'])} s (simulated; {res.steps} steps in {res.wall_s:.1f} s)\n"
             f"assembly {fmt(res.construction.get('assembly'))} s, disassembly "
             f"{fmt(res.construction.get('disassembly'))} s; structures {' -> '.join(res.levels_used) or '-'}")
    if res.faults_spec:
        fl = res.faults
        human += (f"\nfaults {res.faults_spec}: {payload['robots_failed']} robots failed, "
                  f"{payload['robots_detected']} detected by the swarm"
                  + (f" (longest delay {payload['max_detection_delay_s']:.1f} s)"
                     if payload['max_detection_delay_s'] is not None else "")
                  + (f"; {res.robots_in_piers} built into piers" if res.robots_in_piers else ""))
        for f in fl[:12]:
            det = (f"detected at {f['detected_s']:.1f} s ({f['how']}, after {f['delay_s']:.1f} s)"
                   if f["detected_s"] is not None else "never detected")
            human += f"\n  robot {f['robot']}: {f['mode']} failure at {f['t_s']:.1f} s while {f['doing']}; {det}"
        if len(fl) > 12:
            human += f"\n  ... {len(fl) - 12} more (--json)"
        for i, pr in enumerate(payload["piers"]):
            human += (f"\npier {i + 1} at {pr['s_cm']:g} cm past the near edge: failed robots {pr['robots']} "
                      f"({len(pr['robots'])} of {pr['needed']}"
                      + (f", complete at {pr['complete_s']:.1f} s)" if pr["complete"] else ", not completed)"))
    for sw in res.switches:
        human += (f"\n  switch to {sw['level']} ({sw['lines']} x {sw['layers']} per row) at t={sw['t_s']:.2f} s, "
                  f"n_g={sw['n_g']}, {sw['rows']} rows")
    if res.violations:
        human += "\nINVARIANT VIOLATIONS:\n  " + "\n  ".join(res.violations[:10])
    if files:
        human += "\nwrote " + ", ".join(files)
    emit(args, payload, human)
    return 1 if res.violations else 0


def soak(args: argparse.Namespace) -> int:
    from swarm_sim.experiments.soak import LIMITS
    from swarm_sim.experiments.soak import soak as do_soak
    from swarm_sim.runner import resolve_engine

    engine = resolve_engine(args.engine)
    check_int(args.runs, "--runs", 1, MAX_RUNS, "randomised runs")
    check_int(args.workers, "--workers", 1, MAX_WORKERS, "worker processes")
    check_seed(args.seed)
    check_float(args.max_time, "--max-time", 0.0, MAX_SIM_TIME_S, what="simulated seconds")
    if args.journal is not None:  # before the draws: a journal that cannot be written is refused now
        out_file(args.journal, "--journal")
    limits = LIMITS if args.limits == "both" else (args.limits,)
    rep = do_soak(args.runs, seed=args.seed, max_time_s=args.max_time, limits=limits, workers=args.workers,
                  progress=lambda it, n: progress(it, "soak", n), journal=args.journal, engine=engine,
                  faults=args.faults)
    guard = "the presets' time-limit guards" if args.max_time is None else f"capped at {args.max_time:g} s"
    reasons = ", ".join(f"{k} {v}" for k, v in sorted(rep["end_reasons"].items())) or "none"
    resumed = f" ({rep['resumed_runs']} from the journal, {rep['wall_s_total']:.0f} s wall in all)" \
        if rep["resumed_runs"] else ""
    if len(rep.get("code_versions", ())) > 1:
        resumed += f" [the journal's draws ran on {len(rep['code_versions'])} code versions: {rep['code_versions']}]"
    human = (f"{rep['runs']} randomised whole runs (limits {', '.join(rep['limits'])}; {guard}) in "
             f"{rep['wall_s']:.0f} s wall{resumed}: {rep['timeouts']} timeouts, {rep['n_violations']} invariant violations, "
             f"{rep['robots_lost']} robots lost, {rep['errors']} runs raised, {rep['skipped_invalid']} draws "
             f"rejected as invalid input\nended: {reasons}; {rep['hand_overs']} recruits handed over"
             + (f"; {rep.get('robots_failed', 0)} robots failed, {rep.get('robots_in_piers', 0)} built into piers"
                if args.faults else ""))
    for v in (rep["violations"][:10] + rep["timeout_draws"][:10] + rep["error_draws"][:10]):
        human += f"\n  {v}"
    emit(args, rep, human)
    return 1 if rep["n_violations"] or rep["robots_lost"] or rep["timeouts"] or rep["errors"] else 0


def params_table(args: argparse.Namespace) -> int:
    from swarm_sim.params import Params
    from swarm_sim.tunables import table

    rows = table(Params())
    w = max(len(r["name"]) for r in rows)
    human = "\n".join(f"{r['name']:<{w}}  {r['kind']:<8} {r['default']!s:>7} {r['unit']:<6} range {r['lo']:g}..{r['hi']:g}   "
                      f"{r['changes']} [{r['source']}]" for r in rows)
    emit(args, {"tunables": rows}, human + "\nset with --set NAME=VALUE or in a preset's TOML; `voidcross optimise "
         "--params ...` tunes the search/timing/watchdog ones (robot: the body and sensors, not tuned)")
    return 0


def bench(args: argparse.Namespace) -> int:
    from swarm_sim.experiments.bench import bench as do_bench

    if args.workload == "thesis":
        from swarm_sim.experiments.bench import workload_bench

        check_int(args.seeds, "--seeds", 1, 1000, "seeds per case")
        check_int(args.repeats, "--repeats", 1, 20, "repeats per run")
        rep = workload_bench(args.seeds, use_numba=False if args.no_numba else None,
                             progress=lambda it, n: progress(it, "thesis workload", n), repeats=args.repeats)
        lines = [f"thesis workload: {rep['runs']} whole runs, {rep['cpu_s_per_run']:.2f} CPU s per run, "
                 f"{rep['us_per_step']:.0f} us per step, {rep['robot_steps_per_s']:.3g} robot-steps/s = "
                 f"{rep['ratio_to_exploration']:.4f} x the exploration rate measured now "
                 f"({rep['reference_exploration_robot_steps_per_s']:.3g}), numba={rep['numba']}"]
        if "speedup_vs_reference" in rep:
            lines.append(f"compiled engine: {rep['speedup_vs_reference']:.1f}x the reference overall, least of "
                         f"{rep['repeats']} repeats (per repeat {', '.join(f'{x:.1f}' for x in rep['speedup_per_repeat'])}"
                         f"x: spread {100 * rep['speedup_spread']:.1f} %) "
                         f"({rep['runs_per_s']:.1f} vs {rep['reference_runs_per_s']:.2f} runs/s), case-D 9/3 "
                         f"{rep.get('case_d_9_3_cpu_ms_per_run', float('nan')):.0f} ms CPU per run; identical runs: "
                         f"{rep['identical_to_reference']}; {100 * rep['kernel_share']:.0f} % of its CPU in the kernel; "
                         f"cold compile {rep.get('cold_compile_s', float('nan')):.1f} s, "
                         f"warm start {rep.get('warm_start_s', float('nan')):.2f} s")
        lines += [f"  {c['preset']} N={c['robots']} w={c['void_width']} {c['limits']}: {c['cpu_s_per_run']:.3f} s/run"
                  + (f" (reference {c['reference_cpu_s_per_run']:.2f} s: {c['speedup_vs_reference']:.1f}x; "
                     f"{100 * c['kernel_share']:.0f} % in the kernel)" if "speedup_vs_reference" in c else "")
                  + f", {c['steps_per_run']} steps, {c['us_per_step']:.1f} us/step, {c['outcomes']}"
                  for c in rep["cases"]]
        emit(args, rep, "\n".join(lines))
        return 0

    check_int(args.robots, "--robots", 2, MAX_BENCH_ROBOTS, "exploring robots")
    check_int(args.steps, "--steps", 1, MAX_BENCH_STEPS, "simulation steps")
    scaling = () if args.no_scaling else (1_000, 3_000, 10_000, 30_000, 100_000)
    rep = do_bench(args.robots, args.steps, scaling=scaling, use_numba=False if args.no_numba else None,
                   progress=lambda it, n: progress(it, "scaling", n))
    human = (f"{rep['robots']} robots x {rep['steps']} steps: {rep['robot_steps_per_s']:.3g} robot-steps/s "
             f"(CPU time; {rep['robot_steps_per_wall_s']:.3g} per wall second, load {rep['load_average_1min']}), "
             f"numba={rep['numba']}\n"
             f"scaling exponent (cost vs robots, 1e3..1e5): {rep['scaling_exponent']}\n"
             f"state of 100,000 robots: {rep['state_bytes_100k'] / 2**20:.1f} MiB; "
             f"process peak RSS {rep['peak_rss_bytes'] / 2**20:.0f} MiB")
    emit(args, rep, human)
    return 0


def pipeline_stage(out: Path, ctx: dict) -> str:
    """One thesis crossing (case D, 9 robots, 3-wide void) with the pipeline's limits;
    writes ``run.json`` under ``out`` and sets ``ctx["sim_run"]``."""
    from swarm_sim.runner import run_scenario

    limits = str(ctx.get("limits") or "derived")
    res = run_scenario("case-d", 9, 3, 1, limits=limits)
    target = Path(out) / "run.json"
    _write_json_atomic(target, res.to_dict(events=True))
    ctx["sim_run"] = target
    outcome = "crossed" if res.success else "retreated" if res.retreated else "timed out"
    return (f"case-d N=9 void=3 ({res.limits_source} limits): {outcome}, robots lost {res.robots_lost}, "
            f"Tt {res.times['Tt']} s -> {target}")


ENGINE_HELP = ("compiled | reference (default: compiled when numba is installed); the same run bit for bit, "
               "compiled fast-forwards the continuous steps (swarm_sim.compiled)")


def register(sub, common) -> None:
    p = sub.add_parser("sim", parents=[common], help="swarm_sim: run, soak and benchmark the swarm simulator",
                       formatter_class=argparse.RawDescriptionHelpFormatter, epilog=RUN_EPILOG)
    ss = p.add_subparsers(dest="sim_command", metavar="SUBCOMMAND", parser_class=type(p))
    p.set_defaults(func=lambda a: (p.print_help(), 0)[1])

    r = ss.add_parser("run", parents=[common], help="one run; prints outcome, times, seed and finder",
                      formatter_class=argparse.RawDescriptionHelpFormatter, epilog=RUN_EPILOG)
    r.add_argument("--preset", default="case-d", help="preset name or TOML path (default case-d)")
    r.add_argument("--robots", type=int, default=None, help="swarm size (default: the preset's)")
    r.add_argument("--void-width", type=int, default=None, help="void width in robot widths (default: preset's)")
    r.add_argument("--seed", type=int, default=0, help="random seed (default 0, as the first run of a sweep)")
    r.add_argument("--limits", default="derived", help="derived | thesis | path to limits.json")
    r.add_argument("--max-time-s", "--max-time", dest="max_time", type=float, default=None,
                   help="simulated-time cap in s (default: the preset's guard)")
    r.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a preset value, e.g. arena_w_cm=800")
    r.add_argument("--faults", default=None, metavar="SPEC",
                   help="robots that fail: rates per robot (drive:0.5/h,sensor:0.2/h,total:0.1/h; also /min, /s) "
                        "and/or a schedule ROBOT@T_S:MODE (3@120:drive); 'none' for none (default: the preset's)")
    r.add_argument("--video", help="write a .mp4 or .gif of the run (under --out)")
    r.add_argument("--snapshots", metavar="DIR", help="write PNG snapshots into DIR (under --out)")
    r.add_argument("--frame-every", type=float, default=0.5, help="simulated s between video frames (default 0.5)")
    r.add_argument("--events", action="store_true", help="include the event log in --json output")
    r.add_argument("--out", default=None, help="output directory (default results/sim when writing files)")
    r.add_argument("--engine", default=None, help=ENGINE_HELP)
    r.set_defaults(func=run)

    s = ss.add_parser("soak", parents=[common], help="many randomised whole runs; reports timeouts, violations, "
                      "lost robots", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=SOAK_EPILOG)
    s.add_argument("--runs", type=int, default=100, help="number of random draws (default 100)")
    s.add_argument("--seed", type=int, default=0, help="seed of the draws (default 0)")
    s.add_argument("--max-time-s", "--max-time", dest="max_time", type=float, default=None,
                   help="cap every run at this many simulated s (default: each preset's guard; a run that "
                        "reaches it counts as a timeout)")
    s.add_argument("--limits", default="both", help="both | derived | thesis | path (default both)")
    s.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    s.add_argument("--journal", default=None, metavar="FILE",
                   help="append every finished draw to FILE (JSON lines); the same command again resumes "
                        "from it (long soaks in slices)")
    s.add_argument("--engine", default=None, help=ENGINE_HELP)
    s.add_argument("--faults", action="store_true",
                   help="robots that fail: half the draws get random fault rates and schedules, the pier "
                        "preset is drawn too (runs with faults use the reference engine)")
    s.set_defaults(func=soak)

    t = ss.add_parser("params", parents=[common],
                      help="every tunable of the behaviour: default, range, unit, what it changes, where it comes from",
                      epilog="examples:\n  voidcross sim params\n  voidcross sim params --json\n"
                             "  voidcross sim run --preset case-d --set recruit_stall_s=10",
                      formatter_class=argparse.RawDescriptionHelpFormatter)
    t.set_defaults(func=params_table)

    b = ss.add_parser("bench", parents=[common], help="exploration-only throughput and scaling",
                      formatter_class=argparse.RawDescriptionHelpFormatter, epilog=BENCH_EPILOG)
    b.add_argument("--robots", type=int, default=10_000)
    b.add_argument("--steps", type=int, default=500)
    b.add_argument("--no-scaling", action="store_true", help="skip the 1e3..1e5 scaling sweep")
    b.add_argument("--no-numba", action="store_true", help="force the numpy back-end")
    b.add_argument("--workload", choices=("exploration", "thesis"), default="exploration",
                   help="exploration (default): N exploring robots; thesis: the thesis's bridge runs to their "
                        "end, as a ratio to the exploration rate measured in the same call")
    b.add_argument("--seeds", type=int, default=3, help="--workload thesis: seeds per case (default 3)")
    b.add_argument("--repeats", type=int, default=3,
                   help="--workload thesis: runs of each (case, seed, engine); the least CPU time counts (default 3)")
    b.set_defaults(func=bench)
