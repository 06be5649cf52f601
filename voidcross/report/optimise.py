"""The report of an optimisation study (``voidcross optimise --report DIR``): the tuned rules
beside the thesis's on held-out seeds, the convergence of the study, and the robustness check.

Written as ``DIR/index.html``, ``DIR/report.md`` and ``DIR/figures/convergence.png`` (+ its
``.csv``). Every figure comes from the study's stored runs (``--db``): rebuilding the report
re-reads them, it never runs the simulator again for what is stored. Times are simulated seconds.
"""

from __future__ import annotations

import time
from pathlib import Path

from .document import Figure, Note, Para, Section, Table, to_html, to_markdown


def _f(v, d: int = 1) -> str:
    return "–" if v is None else f"{v:.{d}f}"


def convergence_figure(study: dict, path: Path) -> None:
    """Each trial's value (dots), the best so far (line) and the thesis's rules (trial 0, dashed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .figures import _csv, _save

    trials = study["trials"]
    xs = [t["number"] for t in trials]
    vals = [t["value"] for t in trials]
    best = study["convergence"]
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    ax.scatter(xs, vals, s=14, color="0.55", label="trial")
    ax.step(range(len(best)), best, where="post", color="C0", label="best so far")
    ax.axhline(study["baseline"]["value"], color="C3", ls="--", lw=1, label="thesis's rules (trial 0)")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("trial")
    ax.set_ylabel("objective (simulated s per crossing run)")
    ax.legend(loc="upper right", fontsize=8)
    _save(fig, path)
    _csv(path, ["trial", "value_s", "best_so_far_s"],
         [[0, study["baseline"]["value"], best[0]]] + [[t, v, b] for t, v, b in zip(xs, vals, best[1:], strict=True)])


def build(study: dict, heldout: dict | None, robust: dict | None, out, tunables: dict) -> dict:
    """Write the report; ``tunables``: ``{name: Tunable}`` for units. Returns the paths."""
    from cubot_cad.atomic import write_text

    out = Path(out)
    fig_dir = out / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    cfg = study["config"]
    intro = [Para(f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from `{study['db']}`: study "
                  f"{study['study_id']}, {len(study['trials'])} trials of CMA-ES over {len(cfg['space'])} tunables, "
                  f"cases {', '.join(cfg['cases'])}, {cfg['limits']} limits, training seeds {cfg['seed']}.."
                  f"{cfg['seed'] + cfg['train_seeds'] - 1} on {len(study['cells'])} cells. Times are simulated seconds.")]
    sections = []
    best, base = study["best"], study["baseline"]
    sec = Section("Study")
    convergence_figure(study, fig_dir / "convergence.png")
    sec.add(Figure("figures/convergence.png", "Convergence: the objective (mean Tt of the training crossings plus "
                   "penalties, per run that should cross) of each trial, the best so far, and the thesis's rules",
                   data="figures/convergence.csv"))
    rows = [[n, tunables[n].unit, tunables[n].kind, _per_case(study["defaults"].get(n, {})),
             _g(best["params"].get(n))] for n in cfg["space"]]
    sec.add(Table(["tunable", "unit", "kind", "thesis's rules", "best trial"], rows,
                  f"best trial {best['number']}: objective {best['value']:.1f} s against {base['value']:.1f} s for "
                  "the thesis's rules (training seeds)"))
    s = best["score"]
    sec.add(Para(f"Best trial on training: {s['crossed']} crossings of {s['should_cross']} runs that should cross "
                 f"(mean Tt {_f(s['mean_tt_s'])} s), {s['no_cross']} failed to cross, {s['timeouts']} timeouts, "
                 f"{s['robots_lost']} robots lost, {s['below_rule']} crossings below the rule."))
    sections.append(sec)
    sec = Section("Held-out seeds: tuned rules against the thesis's")
    if heldout is None:
        sec.add(Note("No held-out evaluation (`voidcross optimise ... --heldout-runs 10` runs it)."))
    else:
        verdict = "accepted" if heldout["accepted"] else "REJECTED: " + "; ".join(heldout["reasons"])
        sec.add(Para(f"Chapter 4's grid at {heldout['runs_per_cell']} runs per cell on seeds from "
                     f"{heldout['seed0']} (never training seeds). Verdict: {verdict}. Pooled median Tt gain over the "
                     f"cases: {_f(heldout['pooled_gain_pct'])} % (95 % bootstrap interval of the tuned/thesis median "
                     f"ratio {_ci(heldout['ratio_ci95'].get('pooled'))})."))
        rows = []
        for case in heldout["thesis"]:
            tb, tt = heldout["thesis"][case], heldout["tuned"][case]
            rows.append([case, _f(tb["Tt_median_s"]), _f(tt["Tt_median_s"]), _f(heldout["gain_pct"].get(case)),
                         _ci(heldout["ratio_ci95"].get(case)), _f(tb.get("Tt_unseen_median_s")),
                         _f(tt.get("Tt_unseen_median_s")), f"{_f(tb['Ta_mean_s'])} / {_f(tt['Ta_mean_s'])}",
                         f"{_f(tb['Td_mean_s'])} / {_f(tt['Td_mean_s'])}", _bounds(tb), _bounds(tt),
                         f"{tb['lost']} / {tt['lost']}"])
        sec.add(Table(["case", "Tt median thesis", "Tt median tuned", "gain %", "ratio 95 %", "unseen cells thesis",
                       "unseen cells tuned", "Ta mean thesis / tuned", "Td mean thesis / tuned",
                       "boundary thesis's rules", "boundary tuned", "lost thesis / tuned"], rows,
                      "per case: Tt and Ta over the crossing runs, Td over the retreats; boundary per width "
                      "1..5: the smallest swarm that always crossed (* where it differs from the counting rule)"))
    sections.append(sec)
    sec = Section("Robustness: faults and obstacles")
    if not robust:
        sec.add(Note("No robustness check (`voidcross optimise ...` runs it unless --no-robustness)."))
    else:
        rows = []
        for name, sides in robust.items():
            if name == "new_runs":
                continue
            for case in sides["thesis"]:
                a, b = sides["thesis"][case], sides["tuned"][case]
                rows.append([name, case, f"{a['crossed']}/{a['runs']}", f"{b['crossed']}/{b['runs']}",
                             _f(a["Tt_median_s"]), _f(b["Tt_median_s"]), f"{a['lost']} / {b['lost']}"])
        sec.add(Table(["scenario", "case", "crossed thesis", "crossed tuned", "Tt median thesis", "Tt median tuned",
                       "lost thesis / tuned"], rows,
                      "the training cells' crossing swarms on held-out seeds, same seeds for both rule sets"))
    sections.append(sec)
    html_path, md_path = out / "index.html", out / "report.md"
    write_text(html_path, to_html("voidcross optimisation report", intro, sections))
    write_text(md_path, to_markdown("voidcross optimisation report", intro, sections))
    return {"html": str(html_path), "markdown": str(md_path), "figures": 1}


def _per_case(by_case: dict) -> str:
    """``{A: 150, B: 300, ...}`` -> ``300 (A: 150)``: the common value and the cases that differ."""
    if not by_case:
        return "–"
    vals = list(by_case.values())
    common = max(set(vals), key=vals.count)
    odd = [f"{c}: {_g(v)}" for c, v in by_case.items() if v != common]
    return _g(common) + (f" ({', '.join(odd)})" if odd else "")


def _g(v) -> str:
    return "–" if v is None else f"{v:g}"


def _ci(ci) -> str:
    return "–" if not ci else f"{ci[0]:.2f}..{ci[1]:.2f}"


def _bounds(summary: dict) -> str:
    return " ".join(f"{b['observed'] if b['observed'] is not None else '–'}{'' if b['ok'] else '*'}"
                    for _, b in sorted(summary["boundary"].items(), key=lambda kv: int(kv[0])))
