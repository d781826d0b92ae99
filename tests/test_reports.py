"""Report folders (vlb_gym.reports): built from a real campaign, checked against independently
computed bounds, and opened in a real headless browser."""

from __future__ import annotations

import copy
import dataclasses
import io
import json
from collections import Counter
import math
import shutil
import re
from decimal import ROUND_FLOOR, Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.stats import beta

from vlb_gym.reports import graph as report_graph
from vlb_gym.reports import write_report_dir
from vlb_gym.reports.attribution import NodeStats, node_stats, plan_behaviors
from vlb_gym.reports.png import encode_png
from vlb_gym.reports.markdown import escape
from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.policies import PolicyRef

# the plan keys shipped behaviors by their file names
MAIN, SUB = "find_goal_and_oscillate.json", "explore_until_goal.json"
STORE = "/tmp/campaign store.sqlite"  # a space: the replay command must quote it
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A real 30-episode campaign of Behavior 2 (with Behavior 1 as sub-behavior) under action
    noise: both successes and failures, of two causes."""
    config = CampaignConfig("VLB-GridExplore-v0", MAIN[:-5], 30, epsilon=0.1,
                            env_kwargs={"action_noise": 2.3})
    results = []
    with Campaign(config) as prepared:
        report = dict(prepared.run(on_result=results.append))
        plan = prepared.plan
    episodes = [r.to_dict() for r in sorted(results, key=lambda r: r.index)]
    assert 0 < report["failures"] < report["episodes"]
    assert len(report["failures_by_cause"]) >= 2
    frames = {"failed episode": [np.full((90, 120, 3), (200, 60, 60), np.uint8)] * 8,
              "successful episode": [np.linspace(0, 1, 64 * 64 * 3).reshape(64, 64, 3)] * 3}
    out = tmp_path_factory.mktemp("report")
    files = write_report_dir(out, report, episodes, plan, frames, store_path=STORE)
    return {"config": config, "report": report, "episodes": episodes, "plan": plan,
            "out": out, "files": files}


def floor5(x: float | Fraction) -> str:
    return str(Decimal(float(x)).quantize(Decimal("0.00001"), rounding=ROUND_FLOOR))


def test_files_written_and_json_round_trips(campaign):
    out, files = campaign["out"], campaign["files"]
    names = {p.relative_to(out).as_posix() for p in files}
    assert {"report.json", "report.md", "report.html", "figures/graph-0.png",
            "figures/graph-1.png", "figures/confidence.png", "figures/episodes.png"} <= names
    assert all(p.is_file() for p in files)
    assert not list(out.glob(".*.tmp")) and not list(out.glob("figures/.*.tmp"))
    written = json.loads((out / "report.json").read_text())
    assert written.pop("nodes")  # each node's statistics: test_node_statistics
    assert written == json.loads(json.dumps(campaign["report"]))
    html = (out / "report.html").read_text()
    assert "http://" not in html and "https://" not in html and " src=\"data:image/png" in html
    assert len(html) < 1_500_000


def test_node_statistics(campaign):
    """report.json's ``nodes`` and report.md's node table against the episodes' own steps,
    grouped here by the node each step names: steps, failed certificates by cause and mean
    step time per primitive node; a sub-behavior node totals its behavior's nodes."""
    nodes = {row["node"]: row for row in
             json.loads((campaign["out"] / "report.json").read_text())["nodes"]}
    steps = [step for episode in campaign["episodes"] for step in episode["steps"]]
    by_node: dict[str, list[dict]] = {}
    for step in steps:
        by_node.setdefault(step["node"], []).append(step)
    primitive_nodes = {name: row for name, row in nodes.items() if row["primitive"]}
    assert set(by_node) <= set(primitive_nodes)
    for name, row in primitive_nodes.items():
        mine = by_node.get(name, [])
        failed = [s for s in mine if not s["certificate"]]
        assert (row["runs"], row["failed"]) == (len(mine), len(failed)), name
        assert row["failures"] == dict(Counter(s["cause"] for s in failed)), name
        if mine:
            assert row["mean_seconds"] == pytest.approx(
                sum(s["seconds"] for s in mine) / len(mine))
            assert row["failure_rate"] == len(failed) / len(mine)
    subs = [row for row in nodes.values() if row["behavior"]]
    assert subs
    for row in subs:  # the sub-behavior's nodes are named after it, "name/node"
        inside = [r for name, r in primitive_nodes.items() if name.startswith(row["behavior"] + "/")]
        assert row["runs"] == sum(r["runs"] for r in inside) > 0
    assert sum(row["failed"] for row in primitive_nodes.values()) == \
        sum(e["failed_certificates"] for e in campaign["episodes"]) > 0
    text = (campaign["out"] / "report.md").read_text()
    assert "| node | what it runs | steps | failed | failure rate | failures by kind |" in text
    for name, row in primitive_nodes.items():
        kinds = "; ".join(f"{cause}: {count}" for cause, count in row["failures"].items()) or "-"
        assert (f"| {escape(name)} | {row['primitive']} | {row['runs']} | {row['failed']} |"
                in text)
        assert escape(kinds) in text


def test_markdown_holds_independently_computed_numbers(campaign):
    report, out = campaign["report"], campaign["out"]
    text = (out / "report.md").read_text()
    n, k, eps, delta = report["episodes"], report["failures"], report["epsilon"], report["delta"]
    # Clopper-Pearson from scipy's beta; confidence as an exact binomial tail in fractions
    low = beta.ppf(delta, n - k, k + 1)
    e = Fraction(eps)
    conf = sum(math.comb(n, j) * e ** j * (1 - e) ** (n - j) for j in range(k + 1, n + 1))
    assert floor5(low) in text and floor5(conf) in text
    assert f"at least **{floor5(low)}**" in text
    assert f"with confidence **{floor5(conf)}**" in text
    assert f"| episodes N | {n} |" in text and f"| failures k | {k} |" in text
    assert f"| successes | {n - k} |" in text
    for group in report["failures_by_cause"]:
        assert f"| {group['cause']} | {group['count']} |" in text
        first = next(e for e in campaign["episodes"] if e["cause"] == group["cause"])
        assert f"`vlb replay '{STORE}' --episode {first['index']}`" in text
    assert "![graph of the main behavior: find\\_goal\\_and\\_oscillate](figures/graph-0.png)" in text
    assert campaign["plan"].content_sha256 in text
    assert "the behavior **find\\_goal\\_and\\_oscillate** succeeds" in text
    assert "uniform over the allowable space" in text


def test_failures_are_attributed_to_nodes(campaign):
    stats = node_stats(plan_behaviors(campaign["plan"]), campaign["episodes"], MAIN)
    failed_steps = sum(not s["certificate"] for e in campaign["episodes"] for s in e["steps"])
    per_node = sum(s.failed for key in (SUB,) for s in stats[key].values()) + sum(
        s.failed for node, s in stats[MAIN].items() if node != "explore")
    assert per_node == failed_steps == sum(e["failed_certificates"] for e in campaign["episodes"])
    assert stats[MAIN]["explore"].failed == sum(s.failed for s in stats[SUB].values())
    assert stats[SUB]["go"].runs > 0 and not stats[SUB]["go"].approximate


def test_html_in_a_real_browser(campaign, tmp_path):
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    if not Path(CHROMIUM).exists():
        pytest.skip(f"chromium is not installed at {CHROMIUM}")
    report, page_path = campaign["report"], campaign["out"] / "report.html"
    url = page_path.resolve().as_uri()
    requests: list[str] = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page()
            page.on("request", lambda request: requests.append(request.url))
            page.goto(url, wait_until="load")
            images = page.eval_on_selector_all(
                "img", "els => els.map(e => [e.dataset.name, e.complete, e.naturalWidth])")
            body = page.inner_text("body")
            rows = page.eval_on_selector_all(
                "table", """tables => tables.filter(t => t.querySelector('th').textContent ===
                'cause').flatMap(t => [...t.querySelectorAll('tbody tr')].map(
                r => [...r.cells].map(c => c.textContent)))""")
            page.screenshot(path=str(tmp_path / "report.png"), full_page=True)
        finally:
            browser.close()
    names = {name for name, _, _ in images}
    assert {"graph-0.png", "graph-1.png", "confidence.png", "episodes.png"} <= names
    assert any(name.startswith("frames-") for name in names)
    assert all(complete and width > 0 for _, complete, width in images), images
    assert "no picture" not in body and "what it runs" in body  # every picture; the node table
    assert f"at least {floor5(report['lower_bound'])}" in body
    assert [(r[0], int(r[1])) for r in rows] == [(g["cause"], g["count"])
                                                 for g in report["failures_by_cause"]]
    assert requests and set(requests) == {url}, requests
    assert (tmp_path / "report.png").read_bytes().startswith(b"\x89PNG")


def _png_size(data: bytes) -> tuple[int, int]:
    from PIL import Image

    assert data.startswith(b"\x89PNG\r\n\x1a\n")
    with Image.open(io.BytesIO(data)) as image:
        image.verify()
    with Image.open(io.BytesIO(data)) as image:
        return image.size


@pytest.mark.parametrize("which", ["dot", "networkx", "broken dot"])
def test_graph_pictures_with_and_without_graphviz(campaign, monkeypatch, which):
    if which == "dot" and shutil.which("dot") is None:
        pytest.skip("Graphviz dot is not on PATH")
    if which != "dot":
        monkeypatch.setattr(report_graph.shutil, "which",
                            lambda name: "/bin/false" if which == "broken dot" else None)
    specs = plan_behaviors(campaign["plan"])
    stats = node_stats(specs, campaign["episodes"], MAIN)
    png, how = report_graph.behavior_png(specs[MAIN], stats[MAIN], "main behavior")
    assert how == ("graphviz" if which == "dot" else "networkx")
    width, height = _png_size(png)
    assert 200 <= width <= 1200 and 100 <= height <= 900


def test_nodes_are_coloured_by_their_failure_rate_not_their_count():
    """33 failures in 37,155 runs is rare (pale), 3 in 4 is not (red), whatever the worst node
    of the graph counts."""
    rare, common = report_graph.failure_shade(33, 37_155), report_graph.failure_shade(3, 4)
    assert rare < 0.05 and common > 0.9
    assert report_graph.failure_colour(0, 10) == report_graph.NO_FAILURE
    assert report_graph.failure_shade(1, 10) == pytest.approx(2 / 3)  # 10%: two decades up
    dot = report_graph.to_dot({"nodes": [{"id": "a", "primitive": "sense"},
                                         {"id": "b", "primitive": "navigate"}],
                               "start": {"node": "a"}, "terminals": ["b"],
                               "edges": [{"from": "a", "to": "b"}]},
                              {"a": NodeStats(37_155, 33), "b": NodeStats(4, 3)}, "t")
    fills = dict(re.findall(r'(n[01]) \[label=.*?fillcolor="(#[0-9a-f]{6})"', dot))
    assert fills["n0"] == report_graph.failure_colour(33, 37_155)
    assert fills["n1"] == report_graph.failure_colour(3, 4) != fills["n0"]
    assert "0.1% of runs" in dot and "100% of runs" in dot


def test_untrusted_strings_are_escaped(campaign, tmp_path):
    evil = '<script>alert("x")</script>'
    report = json.loads(json.dumps(campaign["report"]))
    report["behavior"] = '<img src=x onerror=alert(1)>"'
    report["failures_by_cause"][0]["cause"] = evil
    episodes = [dict(e) for e in campaign["episodes"]]
    first = next(e for e in episodes if e["rho"] < 0)
    first.update(cause=evil, reason=evil + " | `x` ``", error=f"Traceback\n{evil}")
    specs = json.loads(json.dumps(plan_behaviors(campaign["plan"])))
    specs[SUB]["nodes"][0]["id"] = 'sense"]; evil [label="\\N'  # DOT injection attempt
    specs[SUB]["edges"][0]["guard"] = evil
    plan = copy.copy(campaign["plan"])  # past the plan's own checks, which refuse such ids
    object.__setattr__(plan, "policy_content", {"behaviors": specs})
    write_report_dir(tmp_path, report, episodes, plan, store_path="/tmp/x';rm -rf ~;'")
    html = (tmp_path / "report.html").read_text()
    assert "<script" not in html and "<img src=x" not in html
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;" in html
    markdown = (tmp_path / "report.md").read_text()
    assert "<script" not in markdown.split("```text")[0] and "&lt;script>" in markdown
    assert "vlb replay '/tmp/x'\"'\"';rm -rf ~;'\"'\"'' --episode" in markdown
    assert (tmp_path / "figures" / "graph-1.png").read_bytes().startswith(b"\x89PNG")


def test_sequential_report(tmp_path):
    config = CampaignConfig("VLB-GridExplore-v0", MAIN[:-5], 1, epsilon=0.1,
                            env_kwargs={"action_noise": 2.3})
    results: list = []
    with Campaign(dataclasses.replace(config, episodes=40, method="sequential")) as prepared:
        report = dict(prepared.run(on_result=results.append))
        plan = prepared.plan
    write_report_dir(tmp_path, report, [r.to_dict() for r in results], plan)
    text = (tmp_path / "report.md").read_text()
    assert f"Decision: **{report['decision']}**" in text
    assert report["test"] in text
    assert "simultaneously for all n" in text and "description only" in text
    assert "vlb replay" not in text  # no store: no commands


def test_old_store_records_and_trained_agents(campaign, tmp_path):
    """Episodes without steps/start/error: failures are attributed by primitive (marked ~);
    a trained agent has no graph, and says so."""
    old = [{k: v for k, v in e.items() if k not in ("steps", "start", "error")}
           for e in campaign["episodes"]]
    write_report_dir(tmp_path / "old", campaign["report"], old, campaign["plan"])
    text = (tmp_path / "old" / "report.md").read_text()
    assert "attributed by primitive" in text
    stats = node_stats(plan_behaviors(campaign["plan"]), old, MAIN)
    navigate_failures = sum(e["cause"].startswith("navigate") for e in old if e["rho"] < 0)
    assert stats[SUB]["go"].failed == navigate_failures and stats[SUB]["go"].approximate
    agent = {"kind": "sb3", "ref": "agents/ppo.zip", "library": None}
    report = {**campaign["report"], "policy": agent, "behavior": "agents/ppo.zip"}
    written = write_report_dir(tmp_path / "agent", report, old,
                               dataclasses.replace(campaign["plan"], policy=PolicyRef(**agent),
                                                   policy_content={}))
    text = (tmp_path / "agent" / "report.md").read_text()
    assert "there is no graph to draw" in text and "the trained agent **agents/ppo.zip**" in text
    assert not any(p.name.startswith("graph-") for p in written)


def test_png_encoder_and_frame_thumbnails():
    from PIL import Image

    rgb = np.random.default_rng(0).integers(0, 256, (37, 53, 3), dtype=np.uint8)
    with Image.open(io.BytesIO(encode_png(rgb))) as image:
        assert np.array_equal(np.asarray(image), rgb)
    grey = np.linspace(0.0, 1.0, 12).reshape(3, 4)
    assert _png_size(encode_png(grey)) == (4, 3)
    with pytest.raises(ValueError):
        encode_png(np.zeros((2, 2, 5)))


def test_the_reports_picture_library_is_a_core_dependency():
    """After the README's plain install (no extra), reports draw their pictures: what they
    import for them is among the package's own dependencies."""
    import tomllib

    project = tomllib.loads((Path(__file__).parent.parent / "pyproject.toml").read_text())
    names = {re.split(r"[<>=\[ ]", d)[0] for d in project["project"]["dependencies"]}
    assert "matplotlib" in names  # plots.py and graph.py draw with it; its pillow writes PNGs


def test_without_matplotlib_or_graphviz_the_report_says_so(campaign, tmp_path, monkeypatch):
    import sys

    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setattr(report_graph.shutil, "which", lambda name: None)
    written = write_report_dir(tmp_path, campaign["report"], campaign["episodes"],
                               campaign["plan"])
    text = (tmp_path / "report.md").read_text()
    assert "no picture (matplotlib, a dependency of vlb-gym, is missing" in text
    assert floor5(campaign["report"]["lower_bound"]) in text
    assert {p.name for p in written} == {"report.json", "report.md", "report.html"}


def test_the_report_states_each_behaviors_promise_and_how_often_it_broke(campaign):
    text = (campaign["out"] / "report.md").read_text()
    for name in ("find_goal_and_oscillate", "explore_until_goal"):
        count = sum(e.get("cause") == f"{name}: promise" for e in campaign["episodes"])
        shown = name.replace("_", "\\_")
        assert f"Promise of {shown}: **" in text
        assert f"broken in **{count}** of 30 episode(s)." in text


def test_a_report_draws_a_bounded_number_of_behavior_graphs(campaign, tmp_path):
    """A plan listing 200 behaviors: the report draws MAX_GRAPHS and says how many it lists."""
    from vlb_gym.reports.content import MAX_GRAPHS

    plan = campaign["plan"]
    specs = dict(plan.policy_content["behaviors"])
    extra = next(iter(specs.values()))
    listed = {**specs, **{f"/tmp/other_{k}.json": extra for k in range(200)}}
    many = dataclasses.replace(plan, policy_content={**plan.policy_content, "behaviors": listed})
    write_report_dir(tmp_path, campaign["report"], campaign["episodes"], many)
    graphs = list((tmp_path / "figures").glob("graph-*.png"))
    assert len(graphs) == MAX_GRAPHS
    assert f"The plan lists {len(listed)} behaviors" in (tmp_path / "report.md").read_text()


@given(count=st.integers(0, 2000), cap=st.integers(2, 64))
def test_a_film_is_thinned_as_it_comes_to_evenly_spaced_frames(count, cap):
    from vlb_gym.verify.replay import FrameSample

    sample = FrameSample(cap)
    for k in range(count):
        sample(np.array([k]))
    kept = [int(f[0]) for f in sample.frames()]
    assert len(kept) <= cap + 1 and kept == sorted(set(kept))
    if count:
        assert kept[0] == 0 and kept[-1] == count - 1  # the first and the last frame
        steps = {b - a for a, b in zip(kept[:-2], kept[1:-1])}
        assert len(steps) <= 1  # evenly spaced but for the last
        assert len(kept) >= min(count, cap // 2)
