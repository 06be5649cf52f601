"""`voidcross report`: built from a sweep database, every figure on disk, thesis values beside ours."""

from __future__ import annotations

import re
import shutil
import sqlite3
import statistics
import subprocess
import tempfile
from html.parser import HTMLParser
from pathlib import Path

import pytest

from swarm_sim.sweeps import SweepSpec, prepare_sweep
from swarm_sim.sweeps.executors import SerialExecutor
from voidcross.report import build_report
from voidcross.report.build import limits_sets, swarm_reach
from voidcross.report.thesis import THESIS_TABLES, thesis_tables

SYNTH = "swarm_sim.sweeps.synthetic:synthetic_run"
THESIS_TEXT = Path("/work/shared/seed/000_7d319682c6b56a76.txt")


def _sweep(db, spec):
    plan = prepare_sweep(spec, db, run_fn=SYNTH)
    with SerialExecutor() as ex:
        for _ in plan.execute(ex):
            pass
    plan.close()


@pytest.fixture(scope="session")
def report_db(tmp_path_factory):
    d = tmp_path_factory.mktemp("report")
    db = d / "all.sqlite"
    _sweep(db, SweepSpec("case-d", (2, 3, 5, 6, 8, 9), (1, 2, 3), runs=4, limits="thesis",
                         overrides={"raise_on_seed": 3}))
    _sweep(db, SweepSpec("case-a", (5, 7, 8, 10), (1, 2, 3, 4, 5), runs=3, limits="thesis"))
    _sweep(db, SweepSpec("large-void", (70,), (6, 7, 8), runs=3, limits="thesis"))
    return db


@pytest.fixture(scope="session")
def small_db(tmp_path_factory):
    db = tmp_path_factory.mktemp("small") / "small.sqlite"
    _sweep(db, SweepSpec("case-a", (5, 7), (1, 2), runs=2, limits="thesis"))
    return db


@pytest.fixture(scope="session")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("inputs")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (d / "fem" / "plots").mkdir(parents=True)
    (d / "fem" / "selection.md").write_text("# Structure selection\n\n| width | structure |\n|---|---|\n"
                                            "| 1-4 | line |\n| 5-6 | arch |\n")
    fig, ax = plt.subplots()
    ax.plot([1, 2], [3, 4])
    fig.savefig(d / "fem" / "plots" / "deflection.png")
    (d / "cad").mkdir()
    fig.savefig(d / "cad" / "cubot.png")
    plt.close(fig)
    return d


@pytest.fixture(scope="session")
def report(report_db, inputs, tmp_path_factory):
    out = tmp_path_factory.mktemp("out") / "report"
    res = build_report(report_db, out, fem_dir=inputs / "fem", cad_dir=inputs / "cad", limits="thesis")
    return out, res


class _Imgs(HTMLParser):
    def __init__(self):
        super().__init__()
        self.srcs = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.srcs.append(dict(attrs).get("src"))


def _img_srcs(html_path: Path) -> list[str]:
    p = _Imgs()
    p.feed(html_path.read_text())
    return p.srcs


def test_every_img_in_the_html_exists_on_disk(report):
    out, res = report
    srcs = _img_srcs(out / "index.html")
    assert len(srcs) == res["figures"] >= 20
    for s in srcs:
        assert s and not s.startswith(("/", "http")), s  # relative: the report can be moved
        f = out / s
        assert f.is_file() and f.stat().st_size > 1000 and f.read_bytes()[:4] == b"\x89PNG", s
    md = (out / "report.md").read_text()
    md_srcs = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    assert sorted(md_srcs) == sorted(srcs)


def test_sections_and_no_data_notes(report):
    out, res = report
    html = (out / "index.html").read_text()
    for needle in ("Structure limits: derived and thesis", "Case D (case-d)", "Case A (case-a)",
                   "Tables 4.4-4.9", "Large voids", "cf. Fig. 4.39", "cf. Fig. 4.36", "cf. Fig. 5.9",
                   "cf. Fig. 5.12", "Structure selection", "assets/fem/plots/deflection.png",
                   "assets/cad/cubot.png", "derived limits", "thesis limits"):
        assert needle in html, needle
    # case-b has no runs: its thesis tables stand alone with a note saying so
    assert "no case-b runs in this database" in html
    # Fig. 5.13 has no separate assembly/disassembly time in the synthetic runs
    assert "assembly/disassembly" in html
    # the raised runs are listed
    assert "synthetic failure for seed 3" in html and res["raised"] == 18


def test_sections_without_data_are_left_out_and_named_once_with_their_command(small_db, tmp_path):
    build_report(small_db, tmp_path / "r")
    html = (tmp_path / "r" / "index.html").read_text()
    md = (tmp_path / "r" / "report.md").read_text()
    for text in (html, md):
        assert text.count("Not in this report") == 1
        assert "structure_fem tables and plots" in text and "voidcross report --fem-dir" in text
        assert "CAD renders and 3D models" in text and "voidcross report --cad-dir" in text
        assert "Robot and connector renders" not in text and "Structure selection and deflection" not in text
    assert all((tmp_path / "r" / s).is_file() for s in _img_srcs(tmp_path / "r" / "index.html"))


def test_a_section_asked_for_is_shown_even_empty(small_db, tmp_path):
    build_report(small_db, tmp_path / "r", fem_dir=tmp_path / "nothing-here")
    html = (tmp_path / "r" / "index.html").read_text()
    assert "Structure selection and deflection" in html and "does not exist" in html


def test_the_reach_table_rows_come_each_from_its_own_record(small_db, tmp_path):
    """Runs under --limits thesis: the 70-robot table's derived row is the derived record's
    own reach, the thesis row the thesis's, computed from each record."""
    from structure_fem.limits import load_limits, thesis_limits

    build_report(small_db, tmp_path / "r", limits="thesis")
    html = (tmp_path / "r" / "index.html").read_text()
    t = html.split("What a swarm of 70 robots can cross", 1)[1].split("</table>", 1)[0]
    rows = {r[0]: r[1:] for r in (re.findall(r"<td>([^<]*)</td>", x) for x in t.split("<tr>")) if r}
    d, th = swarm_reach(load_limits("derived"), 70), swarm_reach(thesis_limits(), 70)
    assert rows["derived"][0] == str(d["widest"]) and rows["thesis"][0] == str(th["widest"])
    if (d["widest"], d["widest_structure"]) != (th["widest"], th["widest_structure"]):
        assert rows["derived"][:2] != rows["thesis"][:2]  # never the same figures under both labels


def _cell(html: str, caption_start: str, row_label: str, col: int) -> str:
    table = html.split(caption_start, 1)[1].split("</table>", 1)[0]
    row = table.split(f"<td>{row_label}</td>", 1)[1].split("</tr>", 1)[0]
    return re.findall(r"<td>([^<]*)</td>", row)[col]


def test_ours_beside_thesis_is_computed_from_the_db(report, report_db):
    out, _ = report
    html = (out / "index.html").read_text()
    con = sqlite3.connect(report_db)
    ta = [r[0] for r in con.execute("SELECT t_a FROM runs WHERE preset='case-a' AND robots=5 AND void_width=1 "
                                     "AND status='ok'")]
    con.close()
    mean, sd = statistics.mean(ta), statistics.stdev(ta)
    cell = _cell(html, "Thesis Table 4.4", "12 cm (1)", 0)
    star = "*" if abs(mean - 54) > sd else ""
    assert cell == f"{mean:.0f} ±{sd:.0f} / 54 (×{mean / 54:.2f}){star}"
    # Table 4.5: the thesis prints '-' where case A crossed
    assert _cell(html, "Thesis Table 4.5", "12 cm (1)", 3).endswith("/ –")


def test_report_moves_when_the_data_moves(small_db, tmp_path):
    db = tmp_path / "m.sqlite"
    shutil.copy(small_db, db)
    con = sqlite3.connect(db)
    con.execute("UPDATE runs SET t_a = t_a + 1000 WHERE preset='case-a' AND robots=5 AND void_width=1")
    con.commit()
    con.close()
    build_report(db, tmp_path / "r")
    html = (tmp_path / "r" / "index.html").read_text()
    first = int(_cell(html, "Thesis Table 4.4", "12 cm (1)", 0).split(" / ")[0].split(" ±")[0])
    assert first > 1000


def test_observed_boundary_follows_the_runs(report):
    out, _ = report
    html = (out / "index.html").read_text()
    # synthetic runs cross iff N >= 3w: for 2-wide voids, 5 never crosses and 6 always does
    t = html.split("case-d: observed crossing boundary", 1)[1].split("</table>", 1)[0]
    rows = [re.findall(r"<td>([^<]*)</td>", r) for r in t.split("<tr>")]
    rows = {r[0]: r[1:] for r in rows if r}
    assert [rows[w][:2] for w in ("1", "2", "3")] == [["2", "3"], ["5", "6"], ["8", "9"]]
    # the rule columns, each from its own record: the runs used the thesis's limits, the derived
    # column is still the derived record's (never the thesis's figures under the derived label)
    from structure_fem.limits import load_limits, thesis_limits

    for label, lim in (("derived", load_limits("derived")), ("thesis", thesis_limits())):
        col = 2 + list(limits_sets("thesis")[0]).index(label)
        for w in ("1", "2", "3"):
            want = str(lim.min_robots(int(w))) if int(w) <= lim.max_span_widths else "–"
            assert rows[w][col] == want, (label, w)


def test_thesis_data_files_name_their_table_and_match_the_thesis_text():
    tables = thesis_tables()
    assert [t.number for t in tables] == ["4.4", "4.5", "4.6", "4.7", "4.8", "4.9"]
    for (fname, number, _, _), t in zip(THESIS_TABLES, tables, strict=True):
        assert t.title.startswith(f"Thesis Table {number}:"), fname
        assert len(t.widths()) == 5 and len(t.values) == 5 * len(t.robots)
    if not THESIS_TEXT.exists():
        pytest.skip(f"thesis text not at {THESIS_TEXT}")
    text = THESIS_TEXT.read_text()
    for t in tables:
        chunk = text.split(f"Table {t.number}:", 1)[1][:1500]
        for w in t.widths():
            m = re.search(rf"^{t.void_cm[w]}(?:cm)? ((?:[-\d]+ ?)+)$", chunk, flags=re.M)
            assert m, (t.number, w)
            printed = [None if c == "-" else float(c) for c in m.group(1).split()]
            assert printed == [t.values[(n, w)] for n in t.robots], (t.number, w)


def test_report_cli_and_bad_db(cli, small_db, tmp_path):
    res = cli("report", "--db", str(small_db), "--out", str(tmp_path / "rep"), "--json")
    assert res.code == 0, res.err
    assert Path(res.json()["html"]).is_file()
    res = cli("report", "--db", str(tmp_path / "missing.sqlite"), "--out", str(tmp_path / "rep2"))
    assert res.code == 2 and len(res.error_lines) == 1 and not (tmp_path / "rep2").exists()


CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else None)


def test_report_loads_in_headless_chromium_with_no_missing_image(report, require_tool):
    require_tool(CHROMIUM, "chromium")
    out, _ = report
    js = ("<script>window.onload=function(){var bad=[];for(const i of document.images){"
          "if(!i.complete||i.naturalWidth===0)bad.push(i.getAttribute('src'))}"
          "document.title='IMAGES:'+document.images.length+':BROKEN:'+bad.length+':'+bad.join(',')}</script>")
    probe = out / "_probe.html"
    probe.write_text((out / "index.html").read_text().replace("loading=\"lazy\"", "").replace("</body>", js + "</body>"))
    with tempfile.TemporaryDirectory() as prof:
        res = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
             "--no-first-run", f"--user-data-dir={prof}", "--virtual-time-budget=10000", "--dump-dom",
             probe.as_uri()], capture_output=True, text=True, timeout=90)
    probe.unlink()
    m = re.search(r"<title>IMAGES:(\d+):BROKEN:(\d+):([^<]*)</title>", res.stdout)
    assert m, res.stderr[-2000:]
    assert int(m.group(1)) >= 20 and m.group(2) == "0", m.group(3)


def test_what_a_swarm_can_cross_is_computed_from_the_record_and_moves_with_it(report):
    """Issue 6: the report states what 70 robots can cross under each record, and why not wider."""
    import dataclasses

    from structure_fem.limits import load_limits
    from voidcross.report.build import swarm_reach

    derived = load_limits("derived")
    r70 = swarm_reach(derived, 70)
    assert r70["widest"] >= 1 and r70["next_needs"] > 70
    assert swarm_reach(derived, r70["next_needs"])["widest"] > r70["widest"]  # more robots, wider void
    # a softer record (only the line, spanning one width less) lowers what the same swarm crosses
    line = derived.levels[0]
    assert r70["widest"] >= line.max_span_widths  # 70 robots cross whatever the line spans
    shorter = dataclasses.replace(line, max_span_widths=line.max_span_widths - 1, min_robots=line.min_robots[:-1])
    softer = dataclasses.replace(derived, levels=(shorter,), piers=None)  # its pier rule was for the old line
    assert swarm_reach(softer, 70)["widest"] == line.max_span_widths - 1 < r70["widest"]
    out, _ = report
    text = "".join(p.read_text() for p in out.glob("*.md"))
    assert "What a swarm of 70 robots can cross" in text


def test_an_image_linked_from_an_included_markdown_file_is_rendered_not_printed(small_db, tmp_path):
    """structure_fem writes `![tip deflection ...](file.png)` in its Markdown: the report shows the
    picture where the text puts it (relinked to the copied asset), never the raw link."""
    fem = tmp_path / "fem"
    (fem / "plots").mkdir(parents=True)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1])
    fig.savefig(fem / "plots" / "tip.png")
    plt.close(fig)
    (fem / "table.md").write_text("# Table\n\n![tip deflection per width](plots/tip.png)\n\nsome text\n")
    out = tmp_path / "r"
    build_report(small_db, out, fem_dir=fem, limits="thesis")
    html = (out / "index.html").read_text()
    assert "![" not in html
    srcs = _img_srcs(out / "index.html")
    assert srcs.count("assets/fem/plots/tip.png") == 1 and (out / "assets/fem/plots/tip.png").is_file()
    assert "](assets/fem/plots/tip.png)" in (out / "report.md").read_text()


def test_every_figure_has_its_numbers_beside_it_and_files_are_world_readable(report):
    out, _ = report
    pngs = sorted((out / "figures").glob("*.png"))
    assert pngs
    for png in pngs:
        csv = png.with_suffix(".csv")
        assert csv.is_file() and len(csv.read_text().splitlines()) >= 2, png.name
    html = (out / "index.html").read_text()
    assert html.count("data, CSV</a>") == len(pngs)
    for f in (out / "index.html", out / "report.md", pngs[0]):
        assert f.stat().st_mode & 0o777 == 0o644, f
    import csv as _csv

    rows = list(_csv.DictReader(open(out / "figures" / "case-a-success.csv")))
    assert {"swarm_size", "void_width", "runs", "crossed"} <= set(rows[0])
    assert sum(int(r["runs"]) for r in rows) == 4 * 5 * 3  # 4 sizes x 5 widths x 3 runs


def test_one_labelled_n_min_per_structure(report):
    """The limits table names the launch rule's N_min and the record's complete-structure count
    apart, and the reach table quotes the launch rule (the 4x2 arch's "needs" equals its N_min)."""
    out, _ = report
    html = (out / "index.html").read_text()
    assert "N_min (launch rule)" in html and "complete structure (record)" in html
    from structure_fem.limits import thesis_limits
    from voidcross.report.build import launch_min, swarm_reach

    lim = thesis_limits()
    r = swarm_reach(lim, 70)
    assert r["next_needs"] == launch_min(lim, r["next"])


def test_figures_are_150_dpi_with_integer_ticks_on_counted_axes(report):
    from PIL import Image

    out, _ = report
    with Image.open(out / "figures" / "case-a-success.png") as im:
        assert round(im.info["dpi"][0]) == 150 and im.size[0] >= 900
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from voidcross.report import figures as F

    fig, ax = plt.subplots()
    ax.plot([3, 4], [0, 1])
    F._integer(ax.xaxis)
    fig.canvas.draw()
    assert all(float(t).is_integer() for t in ax.get_xticks())
    plt.close(fig)


def test_the_report_plays_a_run_and_draws_the_3d_model_in_headless_chromium(small_db, tmp_path, require_tool):
    """The interactive parts (issue 17): the player loads with no script or resource error,
    advances frames when played, marks the run's events, shows a clicked robot's state; the
    GLB (here a box written by trimesh) is drawn by the vendored three.js."""
    require_tool(CHROMIUM, "chromium")
    import trimesh

    cad = tmp_path / "cad"
    cad.mkdir()
    box = trimesh.creation.box((120, 120, 100))
    box.visual.face_colors = [200, 60, 40, 255]  # a painted part, as the CAD's GLBs have
    box.export(cad / "cubot.glb")
    out = tmp_path / "r"
    build_report(small_db, out, cad_dir=cad, limits="thesis",
                 watch={"preset": "case-d", "robots": 5, "void_width": 1, "seed": 1, "limits": "thesis"})
    assert (out / "vendor" / "three-0.147.0" / "three.min.js").is_file()  # no network at view time
    js = ("<script>window.addEventListener('load',function(){var P=window.vcPlayer,r={};r.n=P.n;r.marks=P.marks;"
          "P.play();setTimeout(function(){r.frame=P.frame();P.pause();P.select(0);r.info=P.info();"
          "r.models=window.vcModels;r.errors=document.body.dataset.vcErrors||'';"
          "document.title='PROBE:'+JSON.stringify(r)},3000)})</script>")
    probe = out / "_probe.html"
    probe.write_text((out / "index.html").read_text().replace("</body>", js + "</body>"))
    with tempfile.TemporaryDirectory() as prof:
        res = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--disable-background-networking", "--no-first-run",
             f"--user-data-dir={prof}", "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()],
            capture_output=True, text=True, timeout=120)
    m = re.search(r"<title>PROBE:([^<]*)</title>", res.stdout)
    assert m, res.stderr[-2000:]
    import html as _html
    import json

    r = json.loads(_html.unescape(m.group(1)))
    assert r["errors"] == "", r["errors"]
    assert r["n"] > 10 and r["frame"] > 0 and r["marks"] >= 3  # seed, landing, releases ...
    assert r["info"].startswith("robot 0: ") and " cm" in r["info"]
    assert r["models"] == {"count": 1, "drawn": 1}


def test_a_recorded_run_is_a_compact_record_of_the_run(tmp_path):
    from voidcross.report import viewer as V

    run = V.record_run("case-d", 5, 1, 1, "thesis", every_s=1.0)
    n = len(run["t_s"])
    assert n >= 10 and all(len(run[k]) == n for k in ("x_cm", "y_cm", "h_rad", "mode", "state", "layer"))
    assert all(len(row) == 5 for row in run["x_cm"])
    kinds = [e[1] for e in run["events"]]
    assert kinds[0] == "seed" and "target_found" in kinds and run["success"]
    assert run["modes"]["3"] == "in structure"
    big = V.record_run("case-d", 5, 1, 1, "thesis", every_s=0.1)  # thinned to the cap, the end kept
    assert len(big["t_s"]) <= V.MAX_FRAMES and big["t_s"][-1] == run["t_s"][-1]


@pytest.mark.parametrize("watch,needle", [("case-d,9", "PRESET,ROBOTS,WIDTH,SEED"), ("case-d,x,3,1", "integers"),
                                          ("case-d,0,3,1", ">= 1"), ("case-d,9,3,-1", "SEED >= 0")])
def test_a_bad_watch_run_is_one_line_exit_2(cli, small_db, tmp_path, watch, needle):
    res = cli("report", "--db", str(small_db), "--out", str(tmp_path / "r"), "--watch", watch)
    assert res.code == 2 and needle in res.error_lines[0] and len(res.error_lines) == 1
    assert not (tmp_path / "r").exists()


def test_the_deviation_from_the_thesis_is_judged_against_our_spread():
    """Cell by cell: ratio ours / thesis, and inside our spread iff |ours - thesis| <= sd."""
    from voidcross.report.compare import compare_table, table_summary
    from voidcross.report.data import Run

    t = next(t for t in thesis_tables() if t.number == "4.6")  # case A, Tt; N=8, 2 widths: 133 s
    assert t.values[(8, 2)] == 133

    def run(tt, seed):
        return Run("case-a", 8, 2, seed, "thesis", True, False, 0, {"Tt": tt}, None, None, None, False)

    close = compare_table(t, [run(120.0, 1), run(140.0, 2)])  # mean 130, sd 14.1: 133 inside
    far = compare_table(t, [run(97.0, 1), run(99.0, 2)])      # mean 98, sd 1.4: 133 outside, faster
    one = compare_table(t, [run(98.0, 1)])                    # one run: spread unknown, not judged
    c_close, c_far, c_one = ((c for c in cells if (c.robots, c.void_width) == (8, 2)).__next__()
                             for cells in (close, far, one))
    assert c_close.inside is True and abs(c_close.ratio - 130 / 133) < 1e-12
    assert c_far.inside is False and abs(c_far.ratio - 98 / 133) < 1e-12
    assert c_one.inside is None and c_one.ours_sd_s is None
    s = table_summary(far)
    assert (s["compared"], s["judged"], s["inside_spread"], s["faster_outside"], s["slower_outside"]) == (1, 1, 0, 1, 0)


def test_the_report_summarises_the_deviation_per_table_with_a_ratio_map(report):
    out, res = report
    by = {t["table"]: t for t in res["thesis_tables"]}
    assert set(by) == {"4.4", "4.5", "4.6", "4.7", "4.8", "4.9"}
    assert by["4.4"]["compared"] > 0 and by["4.4"]["limits"] == "thesis"
    assert by["4.7"]["compared"] == 0  # no case-b runs in the database
    cells = res["thesis_cells"]["4.4"]
    assert {"ratio", "inside", "ours_sd_s", "thesis_s"} <= set(cells[0])
    assert (out / "figures" / "thesis_table_4_4_ratio.png").is_file()
    assert (out / "figures" / "thesis_table_4_4_ratio.csv").is_file()
    assert not (out / "figures" / "thesis_table_4_7_ratio.png").exists()
    assert "how far ours is from the thesis" in (out / "report.md").read_text()


# ------------------------------------------------------------------ issue 14: the thesis's figures beside ours
def _figure_refs_in_the_report_code() -> set[str]:
    """Every thesis figure the report's code cites: FIG_REFS, the large-void section's numbers and
    any literal "Fig. 4.xx" left in build.py."""
    from voidcross.report import build as B

    refs = set(B.LARGE_VOID_FIG_REFS.values())
    for times, *others in B.FIG_REFS.values():
        refs |= set(times or ())
        refs |= {r.removeprefix("Fig. ") for r in others if r}
    refs |= set(re.findall(r"Fig\. (\d+\.\d+)", Path(B.__file__).read_text()))
    return refs


def test_thesis_figures_quote_the_thesis_text_verbatim_at_their_line():
    """figures.toml: each caption and finding occurs verbatim in the thesis text once whitespace and
    line-break hyphenation are normalised (normalise_text), the caption where `line` says."""
    from voidcross.report.thesis import ThesisFigure, normalise_text, thesis_figures

    assert normalise_text("the posi-\n\n tions of  x\n\ny") == "the positions of x y"
    figs = thesis_figures()
    assert len(figs) >= 20 and all(isinstance(f, ThesisFigure) for f in figs.values())
    for n, f in figs.items():
        assert re.fullmatch(r"\d\.\d+", n) and f.number == n
        for quote in (f.caption, f.finding):
            assert quote == normalise_text(quote) and quote.endswith("."), (n, quote)
        assert 1 <= len(re.findall(r"[.?!](?= [A-Z]|$)", f.finding)) <= 3, (n, f.finding)  # 1-3 sentences
    if not THESIS_TEXT.exists():
        pytest.skip(f"thesis text not at {THESIS_TEXT}")
    text = THESIS_TEXT.read_text()
    lines = text.splitlines()
    whole = normalise_text(text)
    for n, f in figs.items():
        label = f"Figure {n}: "
        assert [k + 1 for k, ln in enumerate(lines) if ln.strip().startswith(label)] == [f.line], n
        # the caption starts at `line` and ends at a line end (not cut short inside a line)
        ends = [normalise_text("\n".join(lines[f.line - 1:f.line - 1 + k])) for k in range(1, 8)]
        assert label + f.caption in ends, (n, ends)
        assert f.finding in whole, n
        near = normalise_text("\n".join(lines[f.finding_line - 1:f.finding_line + 40]))
        assert 0 <= near.find(f.finding) < len(normalise_text(lines[f.finding_line - 1])), (n, f.finding_line)


def test_every_figure_the_report_cites_has_the_thesis_words():
    from voidcross.report.thesis import thesis_figures

    refs = _figure_refs_in_the_report_code()
    assert {"4.13", "4.18", "4.23", "4.39", "4.43", "5.9", "5.13"} <= refs
    assert refs == set(thesis_figures())  # each cited figure has an entry, and no entry is uncited


def test_the_report_quotes_the_thesis_beside_our_figure(report):
    """Right after each of our figures with a thesis equivalent: the thesis's caption and finding,
    quoted; figures without one (case A's times) have none."""
    import html as _html

    from voidcross.report.thesis import thesis_figures

    out, _ = report
    figs = thesis_figures()
    md = (out / "report.md").read_text()
    blocks = md.split("\n\n")
    quoted, plain = {}, 0
    for k, b in enumerate(blocks):
        if not b.startswith("!["):
            continue
        caption = blocks[k + 1]
        m = re.search(r"cf\. Fig\. (\d+\.\d+)", caption)
        after = blocks[k + 2]
        if m and m.group(1) in figs:
            f = figs[m.group(1)]
            assert after == f"**Thesis, Fig. {f.number}** ({f.caption}): “{f.finding}”", caption
            quoted[f.number] = caption
        else:
            plain += 1
            assert not after.startswith("**Thesis, Fig."), caption
    assert {"4.39", "4.40", "4.41", "4.42", "4.43", "4.36", "4.37", "4.38", "4.13",
            "5.9", "5.10", "5.11", "5.12"} <= set(quoted)
    assert quoted["4.39"].startswith("*case-d: ") and quoted["4.13"].startswith("*case-a: ")
    assert plain >= 5  # case A's time figures, the limits plot, the ratio maps ...
    html = (out / "index.html").read_text()
    f = figs["4.39"]
    assert f"<b>Thesis, Fig. 4.39</b> ({_html.escape(f.caption)}): “{_html.escape(f.finding)}”" in html
    assert html.index("cf. Fig. 4.39") < html.index(_html.escape(f.finding)) < html.index("cf. Fig. 4.40")
