"""`voidcross cad`: cubot_cad: parametric robots, printable exports, mass properties.

Sub-commands: ``export`` (STL/STEP/3MF per part, GLB per robot and of a CuBot bridge,
manifest, robot_properties.json, docked pairs), ``dock`` (docked-pair gaps and interference), ``check``
(printability of exported STLs), ``render`` (PNG of robots and docked pairs),
``pier`` (a column of CuBots stacked top-down: heights, mass, checks, STEP/GLB),
``bench`` (time of a full export in a fresh process). cadquery is imported
only when a sub-command runs.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

from cubot_cad.part import (
    DEFAULT_CLEARANCE_MM,
    MAX_CLEARANCE_MM,
    MIN_CLEARANCE_MM,
    clearance_range_text,
)
from voidcross.output import emit, out_dir, progress

EPILOG = """examples:
  voidcross cad export                            all robots: STL + STEP + GLB + manifest into exports/
  voidcross cad export --robot cubot --format stl,step,3mf --material pla --out /tmp/cubot
  voidcross cad export --clearance-mm 0.3         looser fit for a worn printer
  voidcross cad export --robot cubot --set wall_mm=3 --set pin_diameter_mm=5.5
                                                  tuned dimensions (each checked by the robot's own validation)
  voidcross cad check --robot cubot --set wall_mm=3   build with them and check the parts (nothing kept)
  voidcross cad dock --json                       docked gap, interference and capture range of every coupling
  voidcross cad check exports/                    watertight, manifold, bed, thinnest wall, slicing
  voidcross cad render --out /tmp/img --docs      PNGs of robots, docked pairs, CuBot bridge (+ docs/img)
  voidcross cad pier --robots 3                   a pier of 3 stacked CuBots: heights, checks, STEP + GLB
  voidcross cad bench                             time `cad export --robot all` incl. import (goal 60 s)
"""

DEFAULT_OUT = "exports"
DEFAULT_PIER_OUT = "results/cad-pier"
BENCH_GOAL_S = 60.0


def _clearance(value: str) -> float:
    try:
        v = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--clearance-mm {value!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"--clearance-mm {value!r} is not a finite number")
    return v


def _resolve(args, robots) -> tuple:
    """Resolve ``--clearance-mm`` and ``--set`` (the same clearance either way) into
    ``args.clearance_mm`` and return the other settings, refusing one that none of ``robots`` has."""
    from cubot_cad.settings import check_applicable, parse_settings, resolve_clearance

    settings = parse_settings(getattr(args, "set", None) or ())
    args.clearance_mm, rest = resolve_clearance(settings, args.clearance_mm, DEFAULT_CLEARANCE_MM)
    check_applicable(rest, robots)
    return rest


def _robots_count(value: str) -> int:
    try:
        return int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--robots {value!r} is not a whole number of robots") from None


def _lean(value: str) -> float:
    try:
        v = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--lean-deg {value!r} is not a number") from None
    return v


def _bar(items, desc, total):
    return progress(items, desc, total)


def _docked(robots, clearance, settings=()):
    from cubot_cad.checks.docking import dock, pairs_for

    names = pairs_for(robots)
    pairs = []
    for n in progress(names, "docking", len(names)):
        pairs.append(dock(n, clearance, settings=settings) if settings else dock(n, clearance))
    return pairs


def do_export(out: Path, robots, formats, material: str, clearance: float, with_dock: bool = True,
              packaged_default: bool = False, settings: tuple = (), slice_parts: bool = False) -> dict:
    """Dock, check and export; all or nothing (a failing docked pair is an InputError, exit 2,
    and nothing is written: see :mod:`cubot_cad.outputs.export`). ``settings``: ``--set`` dimensions;
    ``slice_parts``: slice every STL with its recorded settings into the manifest (``--slice``)."""
    from cubot_cad.errors import InputError
    from cubot_cad.outputs.export import export_robots
    from cubot_cad.part import check_clearance
    from cubot_cad.part import material as mat
    from cubot_cad.robots.registry import ROBOT_NAMES, make_robot
    from cubot_cad.settings import settings_text

    check_clearance(clearance, "--clearance-mm")
    mat(material)
    if packaged_default and tuple(robots) != ROBOT_NAMES:
        raise InputError("--packaged-default needs --robot all (the packaged file lists every robot)")
    if packaged_default and settings:
        raise InputError(f"--packaged-default with --set {settings_text(settings)}: the packaged file holds the "
                         "default robots")
    if packaged_default and not slice_parts:
        raise InputError("--packaged-default needs --slice: the packaged record carries the printed mass "
                         "(the slicer's grams at each part's print settings), not the solid model's")
    for name in robots:  # every robot builds with the settings before any docking or writing
        make_robot(name, clearance, settings)
    t0 = time.perf_counter()
    pairs = _docked(robots, clearance, settings) if with_dock else None
    stack = _stack_fields(robots, clearance, pairs, settings)  # before anything is written
    if slice_parts:
        from cubot_cad.checks.slicing import slicer_path

        if slicer_path() is None:
            raise InputError("--slice needs prusa-slicer on PATH (Debian: apt-get install prusa-slicer)")
        if "stl" not in formats:
            raise InputError(f"--slice needs stl in --format, got {','.join(formats)}")
    res = export_robots(robots, out, formats, material, clearance, progress=_bar, pairs=pairs, settings=settings,
                        slice_parts=slice_parts)
    if stack:
        from cubot_cad.piers.pier import add_record_fields

        add_record_fields(res.properties, stack)
    summary = [p.summary() for p in pairs or []]
    payload = {
        "out": str(out), "material": material.upper(), "clearance_mm": clearance, "settings": dict(settings),
        "formats": list(formats),
        "parts": len(res.parts), "printed_items": sum(p.quantity for p in res.parts),
        "all_watertight": all(p.watertight for p in res.parts), "robots": {
            k: {kk: v[kk] for kk in ("printed_mass_g", "total_mass_g", "com_mm", "envelope_mm")}
            for k, v in res.robots.items()},
        "docked_pairs": summary, "manifest": str(res.manifest), "robot_properties": str(res.properties),
        "step": res.step_files, "glb": res.glb_files, "seconds": round(time.perf_counter() - t0, 2),
    }
    if packaged_default:
        from cubot_cad.properties import RobotPropertiesFile, default_properties_path

        RobotPropertiesFile.load(res.properties).save(default_properties_path())
        payload["packaged_default"] = str(default_properties_path())
    return payload


def _stack_fields(robots, clearance: float, pairs, settings: tuple = ()) -> dict:
    """Standing height, stack pitch and deck height (with their sources) of every exported robot
    that stacks (has the top-down coupling), for its properties record: the pitch and the deck
    height from the measured docked pair and the docked deck, or the designed ones when the export
    runs without docking. (``export_robots`` writes the same fields; computed here first, before
    anything is written.)"""
    from cubot_cad.piers.pier import stack_fields
    from cubot_cad.robots.registry import make_robot

    out = {}
    for name in robots:
        f = stack_fields(make_robot(name, clearance, settings), pairs)
        if f:
            out[name] = f
    return out


def run_export(args) -> int:
    from cubot_cad.outputs.export import parse_formats
    from cubot_cad.part import check_clearance, material
    from cubot_cad.robots.registry import parse_robots
    from cubot_cad.settings import settings_text

    robots = parse_robots(args.robot)
    formats = parse_formats(args.format)
    settings = _resolve(args, robots)
    check_clearance(args.clearance_mm, "--clearance-mm")
    material(args.material)
    # --out is checked now but created only when the export succeeds (a failed one leaves no trace)
    payload = do_export(out_dir(args.out, create=False), robots, formats, args.material, args.clearance_mm,
                        with_dock=not args.no_dock, packaged_default=args.packaged_default, settings=settings,
                        slice_parts=args.slice)
    tuned = f", {settings_text(settings)}" if settings else ""
    lines = [f"exported {payload['parts']} distinct parts ({payload['printed_items']} printed items) of "
             f"{', '.join(robots)} to {payload['out']} in {payload['seconds']:.1f} s "
             f"({payload['material']}, clearance {args.clearance_mm:g} mm{tuned})"]
    for name, r in payload["robots"].items():
        lines.append(f"  {name}: printed {r['printed_mass_g']:.1f} g, total {r['total_mass_g']:.1f} g, "
                     f"COM {r['com_mm']} mm")
    for p in payload["docked_pairs"]:
        lines.append(f"  {p['pair']}: gap {p['gap_mm']:.2f} mm, interference {p['interference_mm3']:.3f} mm^3")
    if payload["glb"]:
        lines.append(f"  3D models (GLB, m): {', '.join(payload['glb'])}")
    lines.append(f"  manifest: {payload['manifest']}\n  properties: {payload['robot_properties']}")
    if "packaged_default" in payload:
        lines.append(f"  packaged default updated: {payload['packaged_default']}")
    emit(args, payload, "\n".join(lines))
    return 0 if payload["all_watertight"] else 1


def run_dock(args) -> int:
    from cubot_cad.checks.docking import PAIRS, ROBOT_OF_PAIR, dock
    from cubot_cad.part import check_clearance
    from cubot_cad.robots.registry import make_robot
    from voidcross.output import parse_choices

    names = parse_choices(args.pair, "--pair", PAIRS)
    robots = tuple(dict.fromkeys(ROBOT_OF_PAIR[n] for n in names))
    settings = _resolve(args, robots)
    check_clearance(args.clearance_mm, "--clearance-mm")
    for r in robots:  # the settings build, before any docking
        make_robot(r, args.clearance_mm, settings)
    if args.out:
        out_dir(args.out, "--out", create=False)  # before the docking checks
    pairs = [dock(n, args.clearance_mm, settings=settings) for n in progress(names, "docking", len(names))]
    rows = [p.summary() for p in pairs]
    captures = {}
    if not args.no_capture:
        from cubot_cad.checks.capture_cache import measure_all

        # cached by the geometry's hash; the misses measured in parallel, one coupling per process
        captures = measure_all([(make_robot(ROBOT_OF_PAIR[p.name], args.clearance_mm, settings), p.name, p)
                                for p in pairs], progress=lambda it, n: progress(it, "capture", n))
        for p, row in zip(pairs, rows, strict=True):
            cap = captures[p.name]
            row["capture"] = None if cap is None else cap.summary()
            if cap is not None and not cap.ok:
                row["ok"] = False
    if args.out:
        from cubot_cad.jsonrecord import write_json_atomic

        d = out_dir(args.out)
        write_json_atomic(d / "docked_pairs.json", {"clearance_mm": args.clearance_mm, "settings": dict(settings),
                                                    "pairs": rows})
        if args.step:
            for p in pairs:
                p.assembly().export(str(d / f"{p.name}.step"), exportType="STEP")
    def cap_text(p):
        if p.name not in captures:
            return ""
        c = captures[p.name]
        if c is None:
            return "   capture n/a (bolted by hand)"
        return (f"   capture {c.min_offset_mm:g} mm / {c.min_angle_deg:g} deg"
                + ("" if c.ok else " FAIL (< 1 mm / 3 deg)"))

    human = "\n".join(f"{p.name:<24} gap {p.gap_mm:7.3f} mm   interference {p.interference_mm3:.4f} mm^3"
                      + (f"   lateral play {p.play_mm:.3f} mm" if p.play_mm is not None else "")
                      + cap_text(p)
                      + ("" if p.ok else f"   FAIL ({'; '.join(p.problems())})") for p in pairs)
    emit(args, {"clearance_mm": args.clearance_mm, "settings": dict(settings), "pairs": rows}, human)
    return 0 if all(r["ok"] for r in rows) else 1


def run_check(args) -> int:
    from cubot_cad.errors import InputError

    if args.samples < 100:
        raise InputError(f"--samples {args.samples} is too few for the thin-wall probe (>= 100)")
    if args.samples > 1_000_000:
        raise InputError(f"--samples {args.samples} is more than the thin-wall probe needs (<= 1,000,000; "
                         "each sample costs memory)")
    build = bool(args.set) or args.robot is not None or args.clearance_mm is not None
    if build:  # check the parts of robots built now with these dimensions (into a temporary directory)
        if args.dir is not None:
            raise InputError(f"cad check {args.dir}: a directory, or --robot/--clearance-mm/--set to build and "
                             "check fresh parts, not both")
        import tempfile

        from cubot_cad.outputs.export import export_robots
        from cubot_cad.robots.registry import make_robot, parse_robots

        robots = parse_robots(args.robot or "all")
        settings = _resolve(args, robots)
        for name in robots:
            make_robot(name, args.clearance_mm, settings)
        tmp = tempfile.TemporaryDirectory(prefix="cad-check-")
        root = Path(tmp.name) / "build"
    else:
        tmp = None
        root = Path(args.dir if args.dir is not None else DEFAULT_OUT)
    try:
        if tmp is None:
            return _check_dir(args, root, None)
        export_robots(robots, root, ("stl",), "abs", args.clearance_mm, progress=_bar, settings=settings)
        return _check_dir(args, root, (robots, args.clearance_mm, settings))
    finally:
        if tmp is not None:
            tmp.cleanup()


def _check_dir(args, root: Path, built) -> int:
    from cubot_cad.checks.check import check_file, slicer_path, stl_files
    from cubot_cad.errors import InputError

    files = stl_files(root)
    do_slice = not args.no_slice
    results, unreadable = [], []
    for f in progress(files, "cad check", len(files)):
        try:
            results.append(check_file(f, root, do_slice=do_slice, samples=args.samples))
        except InputError as exc:  # unreadable: report it and go on with the others
            unreadable.append({"file": str(f.relative_to(root)), "error": str(exc)})
    rows = []
    for r in results:
        row = dict(vars(r))
        row["ok"] = r.ok
        rows.append(row)
    bad = [r for r in results if not r.ok]
    slicer = slicer_path()
    payload = {"dir": str(root) if built is None else None, "files": len(results) + len(unreadable), "failed": len(bad),
               "unreadable": unreadable,
               "slicer": slicer or None,
               "slicing": "ran" if (slicer and do_slice) else ("disabled (--no-slice)" if not do_slice else
                                                               "skipped: prusa-slicer not on PATH"),
               "parts": rows}
    lines = []
    if built is not None:
        from cubot_cad.settings import settings_text

        robots, c, settings = built
        payload["built"] = {"robots": list(robots), "clearance_mm": c, "settings": dict(settings)}
        lines.append(f"built {', '.join(robots)} (clearance {c:g} mm" + (f", {settings_text(settings)}" if settings
                                                                        else "") + "); nothing kept")
    for r in results:
        flags = []
        if not r.watertight:
            flags.append("not watertight")
        if not r.manifold:
            flags.append("not manifold")
        if not r.fits_bed:
            flags.append(f"does not fit the bed ({r.size_mm})")
        if not r.wall_ok:
            flags.append(f"thinnest wall {r.thinnest_wall_mm} mm < 0.8 mm")
        sl = r.slice or {}
        sliced = (f", print {sl.get('print_time')}, {sl.get('filament_g')} g filament, "
                  f"{sl.get('printed_mass_g')} g printed ({sl.get('settings_source')})" if sl.get("ok") else "")
        if sl and sl.get("ok") is False and not sl.get("skipped"):
            flags.append(f"slice failed: {sl.get('detail')}")
        lines.append(f"{'ok  ' if r.ok else 'FAIL'} {r.file}: wall >= {r.thinnest_wall_mm} mm, "
                     f"size {r.size_mm} mm{sliced}" + (f" [{'; '.join(flags)}]" if flags else ""))
    if slicer and do_slice:  # per robot: print time, filament, printed vs solid-model mass
        from cubot_cad.checks.check import slicing_totals
        from cubot_cad.checks.slicing import duration_text

        totals = slicing_totals(results, root)
        payload["slicing_totals"] = totals
        for name, t in totals.items():
            lines.append(f"{name}: {t['sliced']}/{t['parts']} parts sliced, print {duration_text(t['print_time_s'])}, "
                         f"filament {t['filament_g']:.1f} g, printed {t['printed_mass_g']:.1f} g; solid model "
                         f"{t['solid_mass_g']:.1f} g" + (f" ({t['solid_over_printed_pct']:+.1f} %)"
                                                        if t["solid_over_printed_pct"] is not None else ""))
    lines.append(f"{len(results) - len(bad)}/{len(results)} parts printable"
                 + (f", {len(unreadable)} unreadable" if unreadable else "") + f"; slicing: {payload['slicing']}")
    emit(args, payload, "\n".join(lines))
    if unreadable:  # bad input: one error line per file, exit 2 (after reporting the readable ones)
        for u in unreadable:
            print(f"error: {u['error']}", file=sys.stderr)
        return 2
    return 0 if not bad else 1


def run_render(args) -> int:
    from cubot_cad.checks.docking import dock, pairs_for
    from cubot_cad.outputs.render import render_bridge, render_pair, render_robot
    from cubot_cad.part import check_clearance
    from cubot_cad.robots.registry import make_robot, parse_robots

    robots = parse_robots(args.robot)
    settings = _resolve(args, robots)
    check_clearance(args.clearance_mm, "--clearance-mm")
    for name in robots:
        make_robot(name, args.clearance_mm, settings)
    d = out_dir(args.out)
    targets = [d] + ([Path("docs/img")] if args.docs else [])
    written = []
    jobs = [("robot", r) for r in robots] + ([("pair", p) for p in pairs_for(robots)] if not args.no_pairs else [])
    if args.exploded:
        from cubot_cad.outputs.exploded import PLANS

        jobs += [("exploded", r) for r in robots if r in PLANS]
    if "cubot" in robots and not args.no_pairs:
        from cubot_cad.outputs.gltf import BRIDGE_NAME

        jobs.append(("bridge", BRIDGE_NAME))
    for kind, name in progress(jobs, "render", len(jobs)):
        for t in targets:
            if kind == "robot":
                written.append(str(render_robot(make_robot(name, args.clearance_mm, settings), t / f"{name}.png")))
            elif kind == "exploded":
                from cubot_cad.outputs.exploded import exploded_view

                written.append(str(exploded_view(make_robot(name, args.clearance_mm, settings),
                                                 t / f"{name}-exploded.png")))
            elif kind == "bridge":
                written.append(str(render_bridge(make_robot("cubot", args.clearance_mm, settings),
                                                 dock("cubot-front-rear", args.clearance_mm, settings=settings),
                                                 t / f"{name}.png")))
            else:
                written.append(str(render_pair(dock(name, args.clearance_mm, settings=settings), t / f"{name}.png")))
    emit(args, {"files": written}, "\n".join(written))
    return 0


def run_pier(args) -> int:
    """A pier of ``--robots`` CuBots stacked top-down: its numbers and checks, printed (or JSON),
    written with a STEP and a GLB of the column to ``--out``; exit 1 when a check fails."""
    from cubot_cad.atomic import write_json, write_via
    from cubot_cad.outputs.gltf import write_glb
    from cubot_cad.part import check_clearance
    from cubot_cad.piers.pier import PierColumn, check_lean, check_robots
    from cubot_cad.robots.registry import make_robot

    k = check_robots(args.robots, "--robots")
    lean = check_lean(args.lean_deg, "--lean-deg")
    settings = _resolve(args, ("cubot",))
    check_clearance(args.clearance_mm, "--clearance-mm")
    robot = make_robot("cubot", args.clearance_mm, settings)
    out_dir(args.out, create=False)  # before any work
    col = PierColumn(robot, k, deck=not args.no_deck)
    payload = col.summary(lean)
    d = out_dir(args.out)
    stem = f"pier-cubot-{k}"
    step, glb, rec = d / f"{stem}.step", d / f"{stem}.glb", d / f"{stem}.json"
    assy = col.assembly()
    write_via(step, lambda p: assy.export(p, exportType="STEP"))
    fresh = col.assembly(fresh=True)
    write_via(glb, lambda p: write_glb(fresh, p))
    payload["files"] = {"step": str(step), "glb": str(glb), "json": str(rec)}
    write_json(rec, payload, allow_nan=False)
    emit(args, payload, _pier_text(payload))
    return 0 if payload["ok"] else 1


def _pier_text(p: dict) -> str:
    ch = p["checks"]
    mark = {True: "ok  ", False: "FAIL"}
    heights = ", ".join(f"k={k} {v:.2f}" for k, v in p["heights_mm"].items())
    st, it, dk, rs = ch["stability"], ch["interference"], ch["docking"], ch["running_surface"]
    surface = ", ".join(f"k={k} {v:.2f}" for k, v in p["running_surface_heights_mm"].items())
    lines = [
        f"pier of {p['robots']} CuBot{'s' if p['robots'] > 1 else ''} stacked {p['coupling']} "
        f"(clearance {p['clearance_mm']:g} mm): running surface {p['running_surface_mm']:.2f} mm above the floor "
        + (f"(the {p['deck']} {p['deck_height_mm']:.2f} mm over the top cover at {p['top_height_mm']:.2f})"
           if p["deck"] else "(the bare top cover: no deck)"),
        f"  standing height {p['standing_height_mm']:.3f} mm (floor to cover top, one robot on its wheels and "
        f"casters), stack pitch {p['stack_pitch_mm']:.3f} mm (docked offset)"
        + (f", deck height {p['deck_height_mm']:.3f} mm (top cover to running deck, docked)" if p["deck"] else ""),
        f"  top cover heights (mm): {heights}",
        f"  running surface heights (mm): {surface}",
        f"  mass {p['mass_kg']:.3f} kg, CoM {p['com_height_mm']:.1f} mm above the floor at "
        f"({st['com_xy_mm'][0]:.2f}, {st['com_xy_mm'][1]:.2f}) mm; plan footprint {p['footprint']['plan_mm']} mm, "
        f"support polygon {p['footprint']['support_polygon_mm']} mm",
        f"  {mark[it['ok']]} interference: max {it['max_mm3']:.3f} mm^3 over {len(it['pairs'])} pair(s) in contact "
        f"(limit {it['limit_mm3']:g})",
        f"  {mark[dk['ok']]} docking: {dk['pair']['pair']} gap {dk['pair']['gap_mm']:.3f} mm (designed "
        f"{dk['pair']['design_gap_mm']:g}); key holds and locks at "
        f"{sum(r['key_holds'] and r['key_locked'] for r in dk['interfaces'])}/{len(dk['interfaces'])} interfaces"
        + (f" ({'; '.join(dk['pair_problems'])})" if dk["pair_problems"] else ""),
    ]
    dd = dk.get("deck")
    if dd:
        lines.append(f"  {mark[dd['ok']]} deck docking: {dd['part']} stands {dd['stand_mm']:.3f} mm on its ring "
                     f"(designed {dd['design_stand_mm']:g}), turned on touching "
                     f"{max(r['interference_mm3'] for r in dd['twist']):.3f} mm^3, docked {dd['interference_mm3']:.3f} mm^3; "
                     f"key holds {'yes' if dd['key_holds'] else 'NO'} ({dd['turned_key_lifted_into_roof_mm3']:.0f} mm^3 "
                     f"into the roof lifted), locked {'yes' if dd['key_locked'] else 'NO'}"
                     + (f" ({'; '.join(dd['problems'])})" if dd["problems"] else ""))
    blocking = [q for q in rs["protrusions"] if q["blocks"]]
    detail = "; ".join(f"{q['part']} {q['height_mm']:.2f} mm high meets "
                       + ", ".join(m["line_part"] for m in q["meets"]) for q in blocking)
    lines.append(f"  {mark[rs['ok']]} running surface ({rs['surface']}): ground clearance of a line robot "
                 f"{rs['ground_clearance_mm']:.2f} mm ({rs['lowest_line_part']}), margin {rs['clearance_margin_mm']:.2f} mm; "
                 f"wheels on it: {'yes' if rs['wheels_on_surface'] else 'NO'}"
                 + (f"; blocked by {detail}" if blocking else "; no protrusion in its track above that"))
    if "ends" in rs:
        e, u = rs["ends"], rs["under_deck"]
        lines.append(f"       deck {u['below_running_surface_mm']:.2f} mm over the highest part under it "
                     f"({u['highest_part']}); ends: {e['slope_deg']:g} deg chamfers {e['drop_mm']:g} mm deep "
                     f"(climb limit {e['climb_limit_deg']:.1f} deg), a robot arriving that low clears the end by "
                     f"{e['arrival_margin_mm']:.2f} mm; flat {e['flat_length_mm']:g} mm (robot {e['robot_length_mm']:g})")
    lines.append(f"  {mark[st['ok']]} stability at {st['lean_deg']:g} deg lean: margin {st['margin_mm']:.2f} mm (CoM "
                 f"{st['com_to_edge_mm']:.2f} mm inside the support polygon; tips at {st['tipping_deg']:.1f} deg)")
    lines.append(f"  files: {p['files']['step']}, {p['files']['glb']}, {p['files']['json']}")
    return "\n".join(lines)


def run_bench(args) -> int:
    """Run `voidcross cad export --robot all` in a fresh interpreter (cadquery import included)."""
    import tempfile

    with tempfile.TemporaryDirectory() as td:
        cmd = [sys.executable, "-m", "voidcross.cli", "cad", "export", "--robot", "all", "--out", td, "--json"]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
    if proc.returncode != 0:
        print(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "export failed", file=sys.stderr)
        return 1
    inner = json.loads(proc.stdout)
    payload = {"command": " ".join(cmd[1:4] + cmd[4:7]) + " --out TMP", "wall_s": round(wall, 2),
               "export_s_in_process": inner["seconds"], "import_and_startup_s": round(wall - inner["seconds"], 2),
               "goal_s": BENCH_GOAL_S, "ratio_to_goal": round(wall / BENCH_GOAL_S, 3)}
    emit(args, payload, f"cad export --robot all: {wall:.1f} s wall incl. cadquery import "
                        f"({payload['ratio_to_goal']:.2f} x the {BENCH_GOAL_S:g} s goal; "
                        f"in-process export {inner['seconds']:.1f} s)")
    return 0


#: Robots the pipeline's cad stage renders (plus the bridge); each render takes a few seconds.
PIPELINE_RENDERS = ("cubot", "octbot", "cube-robot", "platform")


def pipeline_renders(out: Path, clearance: float = 0.2, robots=PIPELINE_RENDERS) -> list[str]:
    """PNGs of the robots and of the CuBot bridge into ``out/img`` (the `cad render` code path)."""
    from cubot_cad.checks.docking import dock
    from cubot_cad.outputs.render import render_bridge, render_robot
    from cubot_cad.robots.registry import make_robot

    img = Path(out) / "img"
    written = [str(render_robot(make_robot(name, clearance), img / f"{name}.png")) for name in robots]
    if "cubot" in robots:
        from cubot_cad.outputs.gltf import BRIDGE_NAME

        written.append(str(render_bridge(make_robot("cubot", clearance), dock("cubot-front-rear", clearance),
                                         img / f"{BRIDGE_NAME}.png")))
    return written


def pipeline_stage(out: Path, ctx: dict) -> str:
    from voidcross.pipeline import StageUnavailable

    try:
        import cadquery  # noqa: F401
        import manifold3d  # noqa: F401
        import trimesh  # noqa: F401
    except ImportError as exc:
        raise StageUnavailable(f"cadquery/trimesh/manifold3d not installed ({exc.name}); "
                               "using the packaged robot_properties.json") from None
    from cubot_cad.checks.slicing import slicer_path
    from cubot_cad.outputs.export import DEFAULT_FORMATS
    from cubot_cad.robots.registry import ROBOT_NAMES

    out = Path(out)
    # sliced as the packaged record is (each part's mass the slicer's grams at its print settings),
    # so the pipeline's structure study derives for that record and finds its packaged launch
    # transients; without prusa-slicer the solid model's masses, and the summary says so
    sliced = slicer_path() is not None
    payload = do_export(out, ROBOT_NAMES, DEFAULT_FORMATS, "abs", 0.2, slice_parts=sliced)
    pngs = pipeline_renders(out, 0.2)
    ctx["robot_properties"] = payload["robot_properties"]
    ctx["cad_dir"] = str(out)
    cub = payload["robots"]["cubot"]
    gaps = ", ".join(f"{p['pair']} {p['gap_mm']:.1f} mm" for p in payload["docked_pairs"]
                     if p["pair"] in ("cubot-front-rear", "cube-robot-front-rear", "octbot-ring"))
    from cubot_cad.properties import RobotPropertiesFile

    record_g = 1e3 * RobotPropertiesFile.load(payload["robot_properties"]).get("cubot").mass_kg
    masses = "sliced masses" if sliced else "solid-model masses (no prusa-slicer on PATH)"
    return (f"{payload['parts']} printable parts of {len(ROBOT_NAMES)} robots, CuBot record {record_g:.1f} g "
            f"({masses}; solid model {cub['total_mass_g']:.0f} g, of it printed parts {cub['printed_mass_g']:.0f} g); "
            f"docked gaps {gaps}; {len(payload['glb'])} GLB models, "
            f"{len(pngs)} renders; {out}/robot_properties.json")


def _add_set(q) -> None:
    from cubot_cad.settings import SETTINGS

    q.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="set a dimension (mm), repeatable: " + "; ".join(
                       f"{s.name} ({', '.join(s.robots)})" for s in SETTINGS.values())
                   + ". Each is checked by the robot's own validation (exit 2 and nothing written if refused)")


#: The mass factors `cad props --scale-mass` accepts: a hundredth to a hundred times the record.
MASS_SCALE_RANGE = (0.01, 100.0)


def run_props(args) -> int:
    """Write a consistent variant of a robot_properties.json: every mass field of the chosen
    robots scaled together (docs/records.md), the source fields saying so."""
    from dataclasses import replace

    from cubot_cad.errors import InputError
    from cubot_cad.properties import RobotPropertiesFile, default_properties_path, load_properties

    f = args.scale_mass
    lo, hi = MASS_SCALE_RANGE
    if not (math.isfinite(f) and lo <= f <= hi):
        raise InputError(f"--scale-mass {f!r} is not a factor in [{lo:g}, {hi:g}]")
    src = Path(args.properties) if args.properties else default_properties_path()
    out = Path(args.out)
    if out.exists() and (out.is_dir() or out.resolve() == src.resolve()):
        what = "a directory" if out.is_dir() else "the input record (write a variant beside it)"
        raise InputError(f"--out {out} is {what}")
    from voidcross.output import out_file

    out_file(out, "--out")
    rec = load_properties(args.properties)
    from voidcross.output import parse_choices

    want = parse_choices(args.robot, "--robot", rec.names)
    note = f"mass x{f:g} (voidcross cad props --scale-mass {f:g})"
    robots, rows = [], []
    for r in rec.robots:
        if r.name in want:
            scaled = r.with_mass_scaled(f)
            scaled = replace(scaled, source=f"{r.source}; {note}",
                             solid_print_mass_source=None if r.solid_print_mass_source is None
                             else f"{r.solid_print_mass_source}; {note}")
            rows.append({"robot": r.name, "mass_kg": [r.mass_kg, scaled.mass_kg],
                         "solid_print_mass_kg": [r.solid_print_mass_kg, scaled.solid_print_mass_kg],
                         "inertia_kg_m2": [list(r.inertia_kg_m2), list(scaled.inertia_kg_m2)]})
            r = scaled
        robots.append(r)
    RobotPropertiesFile(tuple(robots), rec.schema_version).save(out)
    lines = [f"{x['robot']}: mass {x['mass_kg'][0]:.4g} -> {x['mass_kg'][1]:.4g} kg"
             + ("" if x["solid_print_mass_kg"][0] is None
                else f", solid print {x['solid_print_mass_kg'][0]:.4g} -> {x['solid_print_mass_kg'][1]:.4g} kg")
             + ", inertia scaled alike" for x in rows]
    emit(args, {"out": str(out), "from": str(src), "scale_mass": f, "robots": rows},
         "\n".join(lines) + f"\nwrote {out} (from {src}); use it with `voidcross fem table --properties {out}`")
    return 0


def register(sub, common) -> None:
    p = sub.add_parser("cad", parents=[common], help="cubot_cad: parametric robots, printable exports, mass properties",
                       description=__doc__.split("\n\n")[0], epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    csub = p.add_subparsers(dest="cad_command", metavar="SUBCOMMAND", parser_class=type(p))
    p.set_defaults(func=lambda a: (p.print_help(), 0)[1])

    def add_common(q, robot=True, tune=True):
        if robot:
            q.add_argument("--robot", default="all", help="cubot, octbot, cube-robot, platform, a comma list or all")
        q.add_argument("--clearance-mm", type=_clearance, default=None, metavar="MM",
                       help=f"print clearance per side on every mating pair, {clearance_range_text()} "
                            f"(default {DEFAULT_CLEARANCE_MM:g}; {MIN_CLEARANCE_MM:g} is a tight fit, "
                            f"{MAX_CLEARANCE_MM:g} a loose one; the same as --set clearance_mm=MM)")
        if tune:
            _add_set(q)

    e = csub.add_parser("export", parents=[common], help="printable STL/STEP/3MF per part, manifest, robot_properties.json",
                        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common(e)
    e.add_argument("--out", default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT}/)")
    e.add_argument("--format", default="stl,step,glb",
                   help="comma list of stl, step, 3mf, glb (default stl,step,glb; glb: one model per robot "
                        "and, with the cubot, bridge-cubot-line.glb)")
    e.add_argument("--material", default="abs", help="abs (1.04 g/cm^3, default) or pla (1.24 g/cm^3)")
    e.add_argument("--no-dock", action="store_true",
                   help="skip the docked pairs (connector gaps then come from the connector geometry alone)")
    e.add_argument("--packaged-default", action="store_true",
                   help="maintainers: also write cubot_cad/data/robot_properties.json (needs --robot all --slice)")
    e.add_argument("--slice", action="store_true",
                   help="slice every STL with its recorded print settings (prusa-slicer; 2-4 min): print time, "
                        "filament and printed grams per part and robot in manifest.json, and the printed mass "
                        "(not the solid model's) in robot_properties.json")
    e.set_defaults(func=run_export)

    d = csub.add_parser("dock", parents=[common], help="docked pairs: gap, interference and capture range of every coupling",
                        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common(d, robot=False)
    d.add_argument("--pair", default="all", help="pair name(s) or all (see cubot_cad.checks.docking.PAIRS)")
    d.add_argument("--out", default=None, help="also write docked_pairs.json (and --step assemblies) here")
    d.add_argument("--step", action="store_true", help="with --out: a STEP assembly per pair")
    d.add_argument("--no-capture", action="store_true",
                   help="skip the capture range (measured by driving one robot in misaligned by 0.5-2 mm and "
                        "1.5-6 deg along each transverse axis; about 1-3 min for all pairs)")
    d.set_defaults(func=run_dock)

    c = csub.add_parser("check", parents=[common], help="printability of exported STLs",
                        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    c.add_argument("dir", nargs="?", default=None, help=f"directory of STLs (default {DEFAULT_OUT}/)")
    c.add_argument("--robot", default=None,
                   help="instead of a directory: build these robots now (cubot, ..., a comma list or all) with "
                        "--clearance-mm and --set and check their parts (nothing is kept)")
    c.add_argument("--clearance-mm", type=_clearance, default=None, metavar="MM",
                   help=f"with a build (see --robot): the print clearance per side, {clearance_range_text()}")
    _add_set(c)
    c.add_argument("--no-slice", action="store_true", help="do not run prusa-slicer even if installed")
    c.add_argument("--samples", type=int, default=3000, help="surface samples of the thin-wall probe (default 3000)")
    c.set_defaults(func=run_check)

    r = csub.add_parser("render", parents=[common], help="PNG renders of robots and docked pairs",
                        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common(r)
    r.add_argument("--out", default=f"{DEFAULT_OUT}/img", help=f"output directory (default {DEFAULT_OUT}/img)")
    r.add_argument("--docs", action="store_true", help="also write docs/img/")
    r.add_argument("--no-pairs", action="store_true", help="robots only")
    r.add_argument("--exploded", action="store_true",
                   help="also the exploded views of docs/assembly.md (<robot>-exploded.png)")
    r.set_defaults(func=run_render)

    pr = csub.add_parser("pier", parents=[common], help="a pier of CuBots stacked top-down: heights, checks, STEP/GLB",
                         epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common(pr, robot=False)
    pr.add_argument("--robots", type=_robots_count, required=True, metavar="K",
                    help="how many CuBots the pier stacks (1-8)")
    pr.add_argument("--out", default=DEFAULT_PIER_OUT,
                    help=f"where pier-cubot-K.step, .glb and .json go (default {DEFAULT_PIER_OUT}/)")
    pr.add_argument("--lean-deg", type=_lean, default=5.0, metavar="DEG",
                    help="lean (or floor slope) the stability margin is given for, 0-45 deg (default 5)")
    pr.add_argument("--no-deck", action="store_true",
                    help="without the pier deck on the top robot (the bare top cover: the running surface fails)")
    pr.set_defaults(func=run_pier)

    pp = csub.add_parser("props", parents=[common],
                         help="write a consistent variant of robot_properties.json (e.g. a heavier robot)",
                         description="Every field that must change together (docs/records.md) changes together: "
                                     "--scale-mass F multiplies mass_kg, solid_print_mass_kg and the inertia tensor "
                                     "of the chosen robots by F, keeps the centre of mass and notes the factor in "
                                     "the record's source fields. No CAD is run.",
                         epilog="examples:\n  voidcross cad props --scale-mass 1.5 --out heavy.json\n"
                                "  voidcross fem table --properties heavy.json",
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    pp.add_argument("--scale-mass", type=float, required=True, metavar="F",
                    help=f"mass factor, {MASS_SCALE_RANGE[0]:g}-{MASS_SCALE_RANGE[1]:g}")
    pp.add_argument("--out", required=True, metavar="FILE", help="the variant record to write (not the input)")
    pp.add_argument("--properties", default=None, metavar="JSON",
                    help="the record to start from (default: the packaged robot_properties.json)")
    pp.add_argument("--robot", default="all", help="robot name(s) in the record, comma list, or all (default all)")
    pp.set_defaults(func=run_props)

    b = csub.add_parser("bench", parents=[common], help="time `cad export --robot all` incl. the cadquery import",
                        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    b.set_defaults(func=run_bench)
