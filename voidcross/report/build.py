"""Build the report: one static HTML page and one Markdown file, every figure as a PNG beside them.

Everything shown is computed from the results database (and the fem/cad
output directories) on every build; the thesis's values come from the data
files in ``thesis_data/`` and are always labelled as the thesis's.
"""

from __future__ import annotations

import os
import re
import shutil
import time
from pathlib import Path

from cubot_cad.atomic import write_text

from . import figures as F
from .compare import cell_text, compare_table, runs_for, table_summary
from .data import RunSet, by_point, grid, load_runs, metric_values, summary
from .document import Figure, MarkdownText, Note, Para, Raw, Section, Table, to_html, to_markdown
from .thesis import thesis_figures, thesis_tables

CASE_NAMES = {"case-a": "Case A", "case-b": "Case B", "case-c": "Case C", "case-d": "Case D"}
#: thesis figure numbers per preset: (times Tt,Ts,Ta,Td,To), seed ids, seed positions, target finder
FIG_REFS = {
    "case-a": (None, "Fig. 4.13", None, None),
    "case-b": (None, "Fig. 4.18", None, None),
    "case-c": (("4.31", "4.32", "4.33", "4.34", "4.35"), "Fig. 4.23", "Fig. 4.24", "Fig. 4.26"),
    "case-d": (("4.39", "4.40", "4.41", "4.42", "4.43"), "Fig. 4.36", "Fig. 4.37", "Fig. 4.38"),
}
TIME_FIG_METRICS = ("Tt", "Ts", "Ta", "Td", "To")
#: thesis figure numbers of the large-void section: seed/target-finder ids, seed position along
#: the edge, total time, time per phase, assembly/disassembly
LARGE_VOID_FIG_REFS = {"ids": "5.9", "edge": "5.10", "tt": "5.11", "phases": "5.12", "asm": "5.13"}
MAX_ASSETS = 80


def _write_atomic(path: Path, text: str) -> None:
    write_text(path, text)  # complete or not at all, 0644 (cubot_cad.atomic)


def _fmt(v, digits: int = 0) -> str:
    return "–" if v is None else f"{v:.{digits}f}"


# ------------------------------------------------------------------ limits
def limits_sets(limits: str | os.PathLike | None) -> tuple[dict, list[str]]:
    """{"derived": StructureLimits, "thesis": ...} and notes on what was unavailable."""
    from structure_fem.errors import InputError as FemInputError
    from structure_fem.limits import load_limits, thesis_limits

    out, notes = {}, []
    spec = str(limits) if limits else "derived"
    # the runs' own limits may be the thesis's: the derived row is still the derived record's
    # (each table row from its own record, never the same figures under two labels)
    label, want = ("derived", "derived") if spec in ("derived", "thesis") else (f"derived ({Path(spec).name})", spec)
    try:
        out[label] = load_limits(want)
    except FemInputError as exc:
        notes.append(f"derived limits unavailable ({exc})")
    out["thesis"] = thesis_limits()
    return out, notes


def _limits_section(limits: dict, notes: list[str], fig_dir: Path, rel: str,
                    reach_sizes: tuple[int, ...] = ()) -> Section:
    sec = Section("Structure limits: derived and thesis")
    sec.add(Para("Which structure spans which void and the smallest swarm that may launch it. `derived` is "
                 "computed by structure_fem from the robots' mechanics (the default for simulations); "
                 "`thesis` is the thesis's own rule (switch every 5 robot widths, N = 3 n_g for a line), "
                 "kept to reproduce its experiments. Both are shown; they are never blended."))
    for n in notes:
        sec.add(Note(n))
    sec.add(Para("Two swarm sizes per structure, named apart: **N_min (launch rule)** is the smallest swarm "
                 "the simulator's counting rule lets build the structure over the void (rows widened at each "
                 "switch; the number every other table and figure here uses), and **complete structure "
                 "(record)** is the limits record's own count, the robots of the whole structure standing "
                 "over the void (the thesis's count for its arches)."))
    for label, lim in limits.items():
        rows = []
        for lvl in lim.levels:
            defl = "–" if lvl.max_deflection_mm is None else f"{lvl.max_deflection_mm:.2f}"
            tip = "–" if lvl.min_tipping_factor is None else f"{lvl.min_tipping_factor:.2f}"
            mr = lvl.min_robots
            rule = [launch_min(lim, w) for w in (lvl.min_span_widths, lvl.max_span_widths)]
            rows.append([lvl.name, lvl.kind, f"{lvl.lines} x {lvl.layers}",
                         f"{lvl.min_span_widths}-{lvl.max_span_widths}", _span(rule),
                         _span((mr[0], mr[-1])), defl, tip])
        sec.add(Table(["structure", "kind", "lines x layers", "void widths", "N_min (launch rule)",
                       "complete structure (record)", "sag at widest (mm)", "tipping factor"], rows,
                      f"{label} limits (source {lim.source}, robot {lim.robot}, clearance {lim.clearance_mm:g} mm)"))
    if len(limits) >= 1:
        rule = {label: {w: launch_min(lim, w) for w in range(1, min(30, lim.max_span_widths) + 1)}
                for label, lim in limits.items()}
        F.limits_plot(limits, fig_dir / "limits.png", rule=rule)
        sec.add(Figure(f"{rel}/limits.png", "Minimum swarm size per void width, derived and thesis limits"))
    for n in reach_sizes or (70,):
        sec.add(_reach_table(limits, n))
    return sec


def _span(v) -> str:
    return f"{v[0]}" if v[0] == v[-1] else f"{v[0]}-{v[-1]}"


def launch_min(lim, width: int, preset: str = "large-void") -> int:
    """N_min of the simulator's counting rule for a ``width``-wide void under ``lim`` (the
    switching structure of ``preset``): the one swarm-size minimum the report quotes."""
    from dataclasses import replace

    from swarm_sim.params import load_preset
    from swarm_sim.resolve import with_limits

    p = with_limits(replace(load_preset(preset), void_width=width, structure="switch"), lim)
    return max(p.min_robots_rule, 2)


def boundaries_for(preset: str, limits: dict, widths: list[int]) -> dict[str, dict[int, int]]:
    """N_min per width for each set of limits; case A adds its stricter +2 (N = 3 n_g + 2)."""
    margin = 2 if preset == "case-a" else 0
    out = {}
    for label, lim in limits.items():
        out[label] = {w: lim.min_robots(w) + margin for w in widths if w <= lim.max_span_widths}
    return out


def thesis_says(ref: str | None, figs: dict) -> Para | None:
    """The thesis's caption of its Fig. ``ref`` ("4.39" or "Fig. 4.39") and its own words on what
    the figure shows (``thesis_data/figures.toml``), as one paragraph to set beside our figure;
    None when ``ref`` is None or not in ``figs``."""
    fig = figs.get(ref.removeprefix("Fig. ")) if ref else None
    if fig is None:
        return None
    return Para(f"**Thesis, Fig. {fig.number}** ({fig.caption}): “{fig.finding}”")


def _add_figure(sec: Section, fig: Figure, ref: str | None, figs: dict) -> None:
    """Our figure, then (when it has a thesis equivalent) what the thesis says of its own."""
    sec.add(fig)
    para = thesis_says(ref, figs)
    if para is not None:
        sec.add(para)


# ------------------------------------------------------------------ per preset
def _mean_table(runs, metric: str, robots: list[int], widths: list[int], caption: str) -> Table:
    pts = by_point(runs)
    rows = []
    for w in widths:
        row = [str(w)]
        for n in robots:
            s = summary(metric_values(pts.get((n, w), []), metric))
            row.append(_fmt(s["mean"]) if s else "–")
        rows.append(row)
    return Table(["void width \\ N"] + [str(n) for n in robots], rows, caption)


def _preset_section(preset: str, rs: RunSet, limits: dict, fig_dir: Path, rel: str) -> Section:
    runs = rs.of(preset)
    title = f"{CASE_NAMES.get(preset, preset)} ({preset})"
    sec = Section(title)
    errors = [e for e in rs.errors if e["preset"] == preset]
    if not runs:
        sec.add(Note(f"no completed {preset} runs ({len(errors)} raised)."))
        return sec
    robots, widths = grid(runs)
    lost = sum(r.robots_lost for r in runs)
    timed_out = sum(r.timed_out for r in runs)
    used = sorted({r.limits for r in runs})
    sec.add(Para(f"{len(runs)} runs ({len(errors)} raised, {timed_out} hit the time limit), swarm sizes "
                 f"{robots[0]}-{robots[-1]}, void widths {widths[0]}-{widths[-1]}, limits used: "
                 f"{', '.join(used)}. Robots lost over all runs: **{lost}** (must be 0)."))
    bnd = boundaries_for(preset, limits, widths)
    name = preset.replace("/", "_")
    F.success_matrix(runs, fig_dir / f"{name}-success.png", preset, bnd)
    sec.add(Figure(f"{rel}/{name}-success.png",
                   f"{preset}: success matrix (swarm size x void width); lines: minimum swarm of each set of limits"))
    # observed boundary vs rules
    pts = by_point(runs)
    rows = []
    for w in widths:
        always = [n for n in robots if pts.get((n, w)) and all(r.success for r in pts[(n, w)])]
        never = [n for n in robots if pts.get((n, w)) and not any(r.success for r in pts[(n, w)])]
        rows.append([str(w), str(max(never)) if never else "–", str(min(always)) if always else "–"]
                    + [str(bnd[k].get(w, "–")) for k in bnd])
    sec.add(Table(["void width", "largest N never crossing", "smallest N always crossing"]
                  + [f"N_min ({k})" for k in bnd], rows, f"{preset}: observed crossing boundary against the rules"))
    # mean time tables
    sec.add(Para("Mean times in simulated seconds (the equivalents of Tables 4.4-4.9; T_d over runs that "
                 "retreated only, as the thesis's 'when the structure fails')."))
    for metric in ("Ta", "Td", "Tt"):
        sec.add(_mean_table(runs, metric, robots, widths, f"{preset}: mean {metric} (s)"))
    # times vs swarm size
    refs = FIG_REFS.get(preset, (None, None, None, None))
    figs = thesis_figures()
    for k, metric in enumerate(TIME_FIG_METRICS):
        ref = f"cf. Fig. {refs[0][k]}" if refs[0] else "mean and 25/75 %"
        fn = f"{name}-time-{metric}.png"
        if F.times_vs_size(runs, metric, fig_dir / fn, preset, ref):
            _add_figure(sec, Figure(f"{rel}/{fn}", f"{preset}: {F.METRIC_NAMES[metric]} vs swarm size, mean and "
                                                  f"25/75 % ({ref})"), refs[0][k] if refs[0] else None, figs)
        else:
            sec.add(Note(f"{preset}: no run recorded {metric} (e.g. no run retreated / crossed)."))
    for attr, what, ref in (("seed_robot", "seed-robot id frequency", refs[1]),
                            ("target_finder", "target-finder id frequency", refs[3])):
        fn = f"{name}-{attr}.png"
        if F.id_frequency(runs, attr, fig_dir / fn, preset, what + (f" (cf. {ref})" if ref else "")):
            _add_figure(sec, Figure(f"{rel}/{fn}", f"{preset}: {what} per swarm size and void width"
                                    + (f" (cf. {ref})" if ref else "")), ref, figs)
        else:
            sec.add(Note(f"{preset}: no {what.split(' id')[0]} recorded."))
    fn = f"{name}-seed-positions.png"
    if F.seed_positions(runs, fig_dir / fn, preset, f"cf. {refs[2]}" if refs[2] else "all runs"):
        _add_figure(sec, Figure(f"{rel}/{fn}", f"{preset}: seed robot positions"
                                + (f" (cf. {refs[2]})" if refs[2] else "")), refs[2], figs)
    else:
        sec.add(Note(f"{preset}: no seed position recorded."))
    return sec


def _thesis_tables_section(rs: RunSet, fig_dir: Path, rel: str) -> tuple[Section, list[dict]]:
    """Tables 4.4-4.9 cell by cell: ours (mean ±sd) / thesis (ours / thesis), a ratio map per
    table and a summary of how far ours is from the thesis (:mod:`voidcross.report.compare`)."""
    sec = Section("Tables 4.4-4.9: the thesis beside ours")
    sec.add(Para("Each cell: ours ±sd / thesis (×ours/thesis), mean simulated seconds; `*`: the thesis's mean "
                 "is outside our run-to-run spread (more than one sample standard deviation from our mean; cells "
                 "with one run are not judged). The thesis's values are read from "
                 "`voidcross/report/thesis_data/*.csv` (one file per table, naming it); ours are recomputed "
                 "from the database, from runs with the thesis's limits when there are any. Void widths in robot "
                 "widths (12 cm robots in cases A and B)."))
    noted = set()
    summaries, overview = [], []
    for t in thesis_tables():
        runs, used = runs_for(t, rs.runs)
        cells = compare_table(t, runs)
        summ = table_summary(cells)
        summaries.append({"table": t.number, "preset": t.preset, "metric": t.metric, "limits": used, **summ,
                          "cells_detail": [c.as_dict() for c in cells]})
        overview.append([f"Table {t.number}", t.preset, t.metric, used, f"{summ['compared']}/{summ['cells']}",
                         _fmt(summ["median_ratio"], 2),
                         "–" if summ["min_ratio"] is None else f"{summ['min_ratio']:.2f}-{summ['max_ratio']:.2f}",
                         f"{summ['inside_spread']}/{summ['judged']}",
                         f"{summ['faster_outside']} / {summ['slower_outside']}"])
        by = {(c.void_width, c.robots): c for c in cells}
        rows = [[f"{t.void_cm[w]} cm ({w})"] + [cell_text(by[(w, n)]) for n in t.robots] for w in t.widths()]
        sec.add(Table(["void \\ N"] + [str(n) for n in t.robots], rows,
                      f"{t.title} [file {t.path.name}; ours: {used} limits]"))
        if summ["compared"]:
            name = f"thesis_table_{t.number.replace('.', '_')}_ratio.png"
            if F.thesis_ratio(cells, fig_dir / name, f"Table {t.number} ({t.preset}, {t.metric}): ours / thesis"):
                sec.add(Figure(f"{rel}/{name}", f"Table {t.number}: ours / thesis per cell (* outside our spread)"))
        if not runs and t.preset not in noted:
            noted.add(t.preset)
            sec.add(Note(f"no {t.preset} runs in this database, so only the thesis's values are filled "
                         f"(`voidcross reproduce --chapter 4 --cases {t.preset[-1].upper()}` runs the thesis's "
                         f"grid, or `voidcross sweep --preset {t.preset} --robots {','.join(map(str, t.robots))} "
                         f"--void-width 1-5 --runs 5 --limits thesis --db ...`, 5 runs per cell as in the thesis)."))
    sec.blocks.insert(1, Table(["table", "preset", "metric", "our limits", "cells compared", "median ours/thesis",
                                "range", "thesis inside our spread", "outside: ours faster / slower"], overview,
                               "how far ours is from the thesis, per table"))
    return sec, summaries


def swarm_reach(lim, robots: int, preset: str = "large-void") -> dict:
    """What a swarm of ``robots`` can cross under the limits ``lim`` with the switching structure.

    Computed from the record and the simulator's rule (rows widened at each switch), never
    looked up: ``{"widest": w or 0, "next": w + 1 or None, "next_structure", "next_needs"}``.
    """
    need = {w: launch_min(lim, w, preset) for w in range(1, lim.max_span_widths + 1)}
    widest = 0
    for w in range(1, lim.max_span_widths + 1):
        if need[w] > robots:
            break
        widest = w
    nxt = widest + 1 if widest < lim.max_span_widths else None
    return {"robots": robots, "widest": widest, "next": nxt,
            "next_structure": lim.level_for(nxt).name if nxt else None,
            "next_needs": need[nxt] if nxt else None,
            "widest_structure": lim.level_for(widest).name if widest else None,
            "max_span": lim.max_span_widths}


def _reach_table(limits: dict, robots: int) -> Table:
    rows = []
    for label, lim in limits.items():
        r = swarm_reach(lim, robots)
        why = (f"{r['next']} widths need the {r['next_structure']} and {r['next_needs']} robots"
               if r["next"] else f"{r['max_span']} widths is the widest structure in these limits")
        rows.append([label, str(r["widest"]), r["widest_structure"] or "–", why])
    return Table(["limits", "widest void crossed (robot widths)", "structure there", "why not wider"], rows,
                 f"What a swarm of {robots} robots can cross (switching structure; computed from each record "
                 "and the simulator's counting rule)")


def _large_void_section(rs: RunSet, fig_dir: Path, rel: str, limits: dict | None = None) -> Section:
    sec = Section("Large voids (Fig. 5.9-5.13 equivalents)")
    large = [p for p in rs.presets() if p.startswith("large")]
    if not large:
        sec.add(Note("no large-void runs in this database (`voidcross sweep --preset large-void --robots 70 "
                     "--void-width 6-10 --runs 10 --db ...`)."))
        return sec
    figs, fr = thesis_figures(), LARGE_VOID_FIG_REFS
    for preset in large:
        runs = rs.of(preset)
        if not runs:
            sec.add(Note(f"no completed {preset} runs."))
            continue
        name = preset.replace("/", "_")
        sec.add(Para(f"{preset}: {len(runs)} runs, swarm sizes {sorted({r.robots for r in runs})}, void widths "
                     f"{sorted({r.void_width for r in runs})}, crossed {sum(r.success for r in runs)}, "
                     f"robots lost {sum(r.robots_lost for r in runs)}."))
        if F.large_void_ids(runs, fig_dir / f"{name}-ids.png", preset):
            _add_figure(sec, Figure(f"{rel}/{name}-ids.png",
                                    f"{preset}: seed and target-finder ids (cf. Fig. {fr['ids']})"), fr["ids"], figs)
        if F.large_void_seed_edge(runs, fig_dir / f"{name}-edge.png", preset):
            _add_figure(sec, Figure(f"{rel}/{name}-edge.png",
                                    f"{preset}: seed position along the edge (cf. Fig. {fr['edge']})"),
                        fr["edge"], figs)
        F.large_void_times(runs, [("T_t", "Tt")], fig_dir / f"{name}-tt.png",
                           f"{preset}: total simulation time (cf. Fig. {fr['tt']})")
        _add_figure(sec, Figure(f"{rel}/{name}-tt.png", f"{preset}: total time vs void width (cf. Fig. {fr['tt']})"),
                    fr["tt"], figs)
        F.large_void_times(runs, [("(a) T_s initial exploration", "Ts"), ("(b) T_a construction", "Ta"),
                                  ("(c) T_o target exploration", "To")], fig_dir / f"{name}-phases.png",
                           f"{preset}: time per phase (cf. Fig. {fr['phases']})")
        _add_figure(sec, Figure(f"{rel}/{name}-phases.png",
                                f"{preset}: T_s, T_a, T_o vs void width (cf. Fig. {fr['phases']})"), fr["phases"], figs)
        has = F.large_void_times(runs, [("(a) assembly", "extra:assembly"), ("(b) disassembly", "extra:disassembly")],
                                 fig_dir / f"{name}-asm.png",
                                 f"{preset}: assembly and disassembly (cf. Fig. {fr['asm']})")
        if has:
            _add_figure(sec, Figure(f"{rel}/{name}-asm.png",
                                    f"{preset}: assembly and disassembly time (cf. Fig. {fr['asm']})"), fr["asm"], figs)
        else:
            for f in (fig_dir / f"{name}-asm.png", fig_dir / f"{name}-asm.csv"):
                f.unlink(missing_ok=True)  # not shown: not left behind either
            sec.add(Note(f"{preset}: the runs do not record separate assembly/disassembly times "
                         f"(Fig. {fr['asm']}); T_a above covers both."))
    return sec


def _copy_assets(src_dir: Path | None, out: Path, sub: str, what: str, title: str) -> Section:
    sec = Section(title)
    if not src_dir:
        sec.add(Note(f"no {what} directory given (--{sub}-dir, or run the pipeline's {sub} stage)."))
        return sec
    src_dir = Path(src_dir)
    if not src_dir.is_dir():
        sec.add(Note(f"{what} directory {src_dir} does not exist."))
        return sec
    mds = sorted(p for p in src_dir.rglob("*.md") if p.is_file())
    pngs = sorted(p for p in src_dir.rglob("*.png") if p.is_file())
    if not mds and not pngs:
        sec.add(Note(f"{src_dir} holds no .md or .png files."))
        return sec
    sec.add(Para(f"Included from `{src_dir}`: {len(mds)} Markdown file(s), {len(pngs)} image(s)."))
    shown = set()
    for md in mds:
        text, used = _relink(md.read_text(errors="replace"), md.parent.relative_to(src_dir), f"assets/{sub}")
        shown |= used
        sec.add(MarkdownText(text, str(md.relative_to(src_dir))))
    dst_root = out / "assets" / sub
    for p in pngs[:MAX_ASSETS]:
        rel = p.relative_to(src_dir)
        dst = dst_root / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(p, dst)
        if rel.as_posix() not in shown:  # already shown where its Markdown placed it
            sec.add(Figure(f"assets/{sub}/{rel.as_posix()}", f"{what}: {rel.as_posix()}"))
    if len(pngs) > MAX_ASSETS:
        sec.add(Para(f"... {len(pngs) - MAX_ASSETS} more images in `{src_dir}` not copied."))
    return sec


_IMG = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)")


def _relink(text: str, md_dir: Path, prefix: str) -> tuple[str, set[str]]:
    """Point the relative image links of an included Markdown file (``md_dir`` relative to its
    source root) at the copies under ``prefix``; returns the text and the images linked."""
    used: set[str] = set()

    def sub(m):
        src = m.group(2)
        if re.match(r"^[a-z]+:|^/", src):
            return m.group(0)
        rel = (md_dir / src).as_posix()
        used.add(rel)
        return f"![{m.group(1)}]({prefix}/{rel})"

    return _IMG.sub(sub, text), used


def pick_watch_run(rs: RunSet) -> dict | None:
    """The run the report plays back when none is named: of the first small-void preset (else
    any), a crossing at the widest void crossed with the fewest robots there."""
    presets = [p for p in rs.presets() if not p.startswith("large")] or rs.presets()
    for preset in presets:
        ok = [r for r in rs.of(preset) if r.success]
        if ok:
            best = max(ok, key=lambda r: (r.void_width, -r.robots, -r.seed))
            return {"preset": preset, "robots": best.robots, "void_width": best.void_width, "seed": best.seed,
                    "limits": best.limits if best.limits in ("derived", "thesis") else "derived"}
    return None


def _watch_section(watch: dict | None, out: Path) -> Section:
    from . import viewer as V

    sec = Section("Watch a run")
    if not watch:
        sec.add(Note("no crossing in this database to play back (or name one: voidcross report --watch "
                     "PRESET,ROBOTS,WIDTH,SEED)."))
        return sec
    from swarm_sim.errors import InputError as SimInputError

    try:
        run = V.record_run(watch["preset"], watch["robots"], watch["void_width"], watch["seed"],
                           watch.get("limits", "derived"))
    except SimInputError as exc:
        sec.add(Note(f"the run {watch} cannot be simulated here: {exc}"))
        return sec
    sec.add(Para(f"The run re-simulated from its seed (`voidcross sim run --preset {run['preset']} --robots "
                 f"{run['robots']} --void-width {run['void_width']} --seed {run['seed']} --limits "
                 f"{run['limits']}`): play it, scrub it, click a robot for its state; the red marks under "
                 "the bar are the run's events (seed chosen, landing, releases, switches, retreat, target "
                 "found)."))
    sec.add(Raw(V.player_html(run), f"Interactive playback: open `index.html` in a browser (the run: "
                                     f"{run['preset']}, {run['robots']} robots, {run['void_width']}-wide void, "
                                     f"seed {run['seed']}, {run['end_reason']})."))
    return sec


def _models_section(cad_dir, out: Path) -> Section | None:
    from . import viewer as V

    glbs = V.find_glbs(Path(cad_dir) if cad_dir else None)
    sec = Section("Robots and bridge in 3D")
    if not glbs:
        sec.add(Note("no GLB models in the CAD directory (`voidcross cad export` writes them)."))
        return sec
    rel = V.copy_vendor(out)
    sec.add(Raw(V.model_html(glbs, rel), "3D models: " + ", ".join(f"`{c}`" for c, _ in glbs)
                + " (rotatable in `index.html`)."))
    return sec


def _errors_section(rs: RunSet) -> Section:
    sec = Section("Runs that raised")
    if not rs.errors:
        sec.add(Para("None: every stored run completed."))
        return sec
    rows = []
    for e in rs.errors[:30]:
        last = (e.get("error") or "").strip().splitlines()[-1:] or [""]
        rows.append([e["preset"], str(e["robots"]), str(e["void_width"]), str(e["seed"]), last[0][:160]])
    sec.add(Table(["preset", "N", "void width", "seed", "error"], rows,
                  f"{len(rs.errors)} run(s) raised (first 30; full tracebacks: voidcross sweep status --json)"))
    return sec


def build_report(db, out, fem_dir=None, cad_dir=None, limits=None, watch: dict | str | None = "auto") -> dict:
    """Write ``out/index.html``, ``out/report.md`` and ``out/figures/*.png``; returns paths and counts.

    ``watch``: the run played back in the page (``{"preset", "robots", "void_width", "seed",
    "limits"}``), ``"auto"`` (:func:`pick_watch_run`) or None (no playback)."""
    rs = load_runs(db)  # validates the database first (InputError, nothing written)
    from dataclasses import replace as _replace

    from .faults import section as faults_section
    from .faults import split as split_faults

    clean, faulty = split_faults(rs.runs)
    all_runs = rs
    rs = _replace(rs, runs=clean)  # the thesis's sections: fault-free runs only
    out = Path(out)
    fig_dir = out / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    for old in [*fig_dir.glob("*.png"), *fig_dir.glob("*.csv")]:
        old.unlink()
    rel = "figures"
    lims, notes = limits_sets(limits)
    presets = all_runs.presets()
    intro = [Para(f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from `{db}`: "
                  f"{len(all_runs.runs)} completed runs ({len(faulty)} with faults), {len(rs.errors)} raised, presets: "
                  f"{', '.join(presets) or 'none'}. Times are simulated seconds.")]
    if rs.sweeps:
        intro.append(Table(["sweep", "started (UTC)", "planned runs", "spec"],
                           [[s["sweep_id"], s["created_utc"], str(s["runs_planned"]),
                             ", ".join(f"{k}={v}" for k, v in sorted(s["spec"].items()))] for s in rs.sweeps],
                           "sweeps recorded in the database"))
    large_sizes = tuple(sorted({r.robots for p in rs.presets() if p.startswith("large") for r in rs.of(p)})[:4])
    sections = [_limits_section(lims, notes, fig_dir, rel, large_sizes)]
    absent: list[tuple[str, str]] = []  # (section, the command that fills it)
    small = [p for p in rs.presets() if not p.startswith("large")]  # fault-free runs
    large = [p for p in rs.presets() if p.startswith("large")]
    if watch is not None and (rs.runs or watch != "auto"):
        sections.append(_watch_section(pick_watch_run(rs) if watch == "auto" else watch, out))
    if small:
        sections += [_preset_section(p, rs, lims, fig_dir, rel) for p in small]
    else:
        absent.append(("small voids (cases A-D)", "voidcross reproduce --chapter 4"))
    comparison: list[dict] = []
    if any(t.preset in small for t in thesis_tables()):
        thesis_sec, comparison = _thesis_tables_section(rs, fig_dir, rel)
        sections.append(thesis_sec)
    else:
        absent.append(("Tables 4.4-4.9 beside ours", "voidcross reproduce --chapter 4"))
    if large:
        sections.append(_large_void_section(rs, fig_dir, rel, lims))
    else:
        absent.append(("large voids", "voidcross reproduce --chapter 5"))
    fault_curves: dict = {}
    if faulty:
        fault_sec, fault_curves = faults_section(clean, faulty, fig_dir, rel)
        sections.append(fault_sec)
    else:
        absent.append(("robots that fail", "voidcross sweep ... --faults 'none;drive:0.5/h'"))
    if fem_dir is not None:  # asked for: shown, with a note if it holds nothing
        sections.append(_copy_assets(fem_dir, out, "fem", "structure_fem output",
                                     "Structure selection and deflection (structure_fem)"))
    else:
        absent.append(("structure_fem tables and plots", "voidcross report --fem-dir DIR (voidcross fem table --out DIR)"))
    if cad_dir is not None:
        sections.append(_copy_assets(cad_dir, out, "cad", "CAD render", "Robot and connector renders (cubot_cad)"))
        models = _models_section(cad_dir, out)
        if models is not None:
            sections.append(models)
    else:
        absent.append(("CAD renders and 3D models", "voidcross report --cad-dir DIR (voidcross cad export --out DIR)"))
    if rs.errors:
        sections.append(_errors_section(rs))
    if absent:
        intro.append(Para("Not in this report (no data for them): "
                          + "; ".join(f"{what} (`{cmd}`)" for what, cmd in absent) + "."))
    for sec in sections:  # each figure's numbers beside it
        for b in sec.blocks:
            if isinstance(b, Figure) and (out / b.src).with_suffix(".csv").is_file():
                b.data = str(Path(b.src).with_suffix(".csv").as_posix())
    title = "voidcross report"
    html_path, md_path = out / "index.html", out / "report.md"
    _write_atomic(html_path, to_html(title, intro, sections))
    _write_atomic(md_path, to_markdown(title, intro, sections))
    n_fig = sum(isinstance(b, Figure) for s in sections for b in s.blocks)
    n_empty = sum(isinstance(b, Note) for s in sections for b in s.blocks)
    return {"html": str(html_path), "markdown": str(md_path), "figures": n_fig, "no_data_notes": n_empty,
            "runs": len(all_runs.runs), "raised": len(rs.errors), "presets": presets,
            "fault_curves": fault_curves,
            "thesis_tables": [{k: v for k, v in c.items() if k != "cells_detail"} for c in comparison],
            "thesis_cells": {c["table"]: c["cells_detail"] for c in comparison}}
