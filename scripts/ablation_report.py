"""Tables, plots, the crop strip and report.html for scripts/ablation.py (numpy + matplotlib).

Everything here is computed from the rows of results.csv (final metrics from `emlt compare`)
and the runs' convergence logs, so the figures and tables agree with each other.
"""
import html
import json
import os

import numpy as np

from ablation_config import PER_PIXEL, SECONDS, fmt_number
from tools.images import crop, read_pfm, tonemap

METRICS = [("mse", "MSE"), ("mse_net", "MSE minus the reference's own noise"), ("relmse", "relMSE"),
           ("mse_no_emitter", "MSE without visible emitters"), ("seconds", "Render time (s)")]
CHAINS_METRIC = ("chains_variance", "Chains' variance across seeds (their MSE, no reference)")


def fmt_value(value):
    """Table text of a mean: 4 significant digits in scientific notation."""
    return f"{value:.3e}"


def fmt_spread(value):
    """Table text of a standard deviation: 2 significant digits."""
    return f"{value:.1e}"


def summarize(values):
    """(mean, sample standard deviation) of the seeds' values; the deviation is 0 for one seed."""
    values = np.asarray(values, dtype=np.float64)
    return float(values.mean()), float(values.std(ddof=1)) if len(values) > 1 else 0.0


def budgets_of(rows):
    """The distinct (kind, value) budgets in rows, per-pixel ones first, in increasing order."""
    return sorted({(r["budget_kind"], r["budget"]) for r in rows}, key=lambda b: (b[0] != PER_PIXEL, b[1]))


def budget_caption(kind, value):
    """'64 samples/mutations per pixel' or 'equal time, 2 s'."""
    if kind == PER_PIXEL:
        return f"{fmt_number(value)} samples/mutations per pixel"
    return f"equal time, {fmt_number(value)} s"


def build_tables(config, rows):
    """Table data: a list of (title, metric, budget, {scene: {method: (mean, std)}}, {scene: best method})."""
    scenes = [s.name for s in config.scenes]
    methods = [m.name for m in config.methods]
    tables = []
    for kind, value in budgets_of(rows):
        for metric, title in METRICS:
            if all(r.get(metric) is None for r in rows):
                continue
            cells, best = {}, {}
            for scene in scenes:
                cells[scene] = {}
                for method in methods:
                    values = [r[metric] for r in rows if r["scene"] == scene and r["method"] == method
                              and r["budget_kind"] == kind and r["budget"] == value and r.get(metric) is not None]
                    if values:
                        cells[scene][method] = summarize(values)
                if cells[scene] and metric != "seconds":
                    best[scene] = min(cells[scene], key=lambda m: cells[scene][m][0])
            tables.append((f"{title} at {budget_caption(kind, value)}", metric, (kind, value), cells, best))
    return tables


def cell_text(cell, bold):
    """'mean ± std', bold when it is the scene's best."""
    if cell is None:
        return "–"
    text = fmt_value(cell[0]) if cell[1] is None else f"{fmt_value(cell[0])} ± {fmt_spread(cell[1])}"
    return f"**{text}**" if bold else text


def build_chains_tables(config, chains):
    """Tables of the chains' variance (one value per scene x method x budget, no spread)."""
    tables = []
    for kind, value in sorted({(c["budget_kind"], c["budget"]) for c in chains}, key=lambda b: (b[0] != PER_PIXEL, b[1])):
        cells, best = {}, {}
        for scene in (s.name for s in config.scenes):
            cells[scene] = {c["method"]: (c["chains_variance"], None) for c in chains
                            if c["scene"] == scene and (c["budget_kind"], c["budget"]) == (kind, value)}
            if cells[scene]:
                best[scene] = min(cells[scene], key=lambda m: cells[scene][m][0])
        tables.append((f"{CHAINS_METRIC[1]} at {budget_caption(kind, value)}", CHAINS_METRIC[0], (kind, value),
                       cells, best))
    return tables


def reference_note(config, rows):
    """The reference's description, with what an indirect-only experiment measures and the floors."""
    text = f"Reference: {config.reference.describe()}"
    if config.indirect_only:
        text += (f", indirect light only. Every run renders direct light separately "
                 f"({config.indirect_direct_spp} spp) and is measured against the indirect reference plus "
                 "that seed's exact direct image, so the MSE is the chains' alone")
    floors = {r["scene"]: r.get("reference_floor") for r in rows if r.get("reference_floor") is not None}
    if floors:
        text += ". The reference's own noise (variance of the mean of its parts), contained in every MSE: " + \
            ", ".join(f"{scene} {fmt_value(floor)}" for scene, floor in floors.items())
    return text + "."


def write_table_md(config, tables, path, engine, rows=()):
    """table.md: one Markdown table per metric and budget, scenes as rows and methods as columns."""
    methods = [m.name for m in config.methods]
    lines = [f"# Ablation: {config.name}", ""]
    if config.description:
        lines += [config.description, ""]
    lines += [f"Engine: {engine}. {reference_note(config, rows)} "
              f"Seeds: {', '.join(map(str, config.seeds))}. "
              "Cells are mean ± standard deviation over seeds; the best mean per scene is bold. "
              "Metrics are `emlt compare --json --scene SCENE` on the saved images.", ""]
    for title, _metric, _budget, cells, best in tables:
        lines += [f"## {title}", "", "| scene | " + " | ".join(methods) + " |",
                  "|---|" + "---:|" * len(methods)]
        for scene, row in cells.items():
            lines.append(f"| {scene} | " + " | ".join(cell_text(row.get(m), best.get(scene) == m)
                                                      for m in methods) + " |")
        lines.append("")
    with open(path, "w") as f:
        f.write("\n".join(lines))


# ---------------------------------------------------------------------------------------------
# Plots


def _pyplot():
    """matplotlib.pyplot with the Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_budget(rows, kind_preference):
    """The budget whose runs a plot uses: the largest of the preferred kind, else of the other kind."""
    for kind in kind_preference:
        values = sorted({r["budget"] for r in rows if r["budget_kind"] == kind})
        if values:
            return kind, values[-1]
    return None


def convergence_curve(logs, x_key):
    """Seeds' logs -> (x, mean mse, min mse, max mse) over checkpoints all seeds share.

    Checkpoints are matched by per_pixel; x is the mean of x_key (per_pixel or seconds) over
    seeds.  The final rows (end of an equal-time run, at different per-pixel counts) are
    averaged into a last point when they are not a shared checkpoint already.
    """
    common = set.intersection(*({row["per_pixel"] for row in log} for log in logs))
    points = []
    for pp in sorted(common):
        picked = [next(row for row in log if row["per_pixel"] == pp) for log in logs]
        points.append(([p[x_key] for p in picked], [p["mse"] for p in picked]))
    finals = [log[-1] for log in logs]
    if any(f["per_pixel"] not in common for f in finals):
        points.append(([f[x_key] for f in finals], [f["mse"] for f in finals]))
    x = np.array([np.mean(p[0]) for p in points])
    errors = [np.array(p[1]) for p in points]
    order = np.argsort(x, kind="stable")
    return (x[order], np.array([e.mean() for e in errors])[order], np.array([e.min() for e in errors])[order],
            np.array([e.max() for e in errors])[order])


def plot_convergence(config, rows, path, x_key):
    """Log-log MSE against per-pixel budget (x_key='per_pixel') or seconds; a panel per scene.

    A line per method is the mean over seeds, its band the seeds' min..max.
    """
    plt = _pyplot()
    budget = plot_budget(rows, [PER_PIXEL, SECONDS] if x_key == "per_pixel" else [SECONDS, PER_PIXEL])
    scenes = config.scenes
    columns = min(3, len(scenes))
    nrows = (len(scenes) + columns - 1) // columns
    fig, axes = plt.subplots(nrows, columns, figsize=(5.0 * columns, 3.8 * nrows), squeeze=False)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for index, scene in enumerate(scenes):
        ax = axes[index // columns][index % columns]
        first = None
        for m_index, method in enumerate(config.methods):
            runs = [r for r in rows if r["scene"] == scene.name and r["method"] == method.name
                    and (r["budget_kind"], r["budget"]) == budget and r["_log"]]
            if not runs:
                continue
            x, mean, low, high = convergence_curve([r["_log"] for r in runs], x_key)
            positive = (x > 0) & (mean > 0)
            color = colors[m_index % len(colors)]
            ax.loglog(x[positive], mean[positive], "o-", ms=3, color=color, label=method.label or method.name)
            if len(runs) > 1:
                ax.fill_between(x[positive], low[positive], high[positive], color=color, alpha=0.2, lw=0)
            if first is None and positive.any():
                first = (x[positive][0], mean[positive][0], x[positive])
        if first is not None and x_key == "per_pixel":
            x0, y0, xs = first
            ax.loglog(xs, y0 * x0 / xs, "k--", lw=0.8, label="1/N")
        if x_key == "per_pixel":
            from matplotlib.ticker import FuncFormatter, NullFormatter
            ax.set_xscale("log", base=2)
            ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: fmt_number(v) if v >= 1 else f"{v:g}"))
            ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_title(scene.name)
        ax.set_xlabel("samples or mutations per pixel" if x_key == "per_pixel" else "seconds")
        ax.set_ylabel("MSE")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    for index in range(len(scenes), nrows * columns):
        axes[index // columns][index % columns].set_visible(False)
    if budget is not None:
        fig.suptitle(f"{config.name}: {budget_caption(*budget)}\n"
                     f"mean of {len(config.seeds)} seeds, band: min..max over seeds", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)


def strip_runs(config, rows):
    """The runs shown in the strip: first seed, largest per-pixel budget (else largest time)."""
    budget = plot_budget(rows, [PER_PIXEL, SECONDS])
    seed = config.seeds[0]
    return {(r["scene"], r["method"]): r for r in rows
            if r["seed"] == seed and (r["budget_kind"], r["budget"]) == budget}, budget, seed


def plot_strip(config, rows, out_dir, path, references):
    """strip.png: per scene a row of crops (reference, then each method), one tone mapping for all."""
    plt = _pyplot()
    shown, budget, seed = strip_runs(config, rows)
    columns = 1 + len(config.methods)
    fig, axes = plt.subplots(len(config.scenes), columns, figsize=(2.3 * columns, 2.55 * len(config.scenes)),
                             squeeze=False)
    for i, scene in enumerate(config.scenes):
        tiles = [("reference\n" + config.reference.describe(), references[scene.name])]
        for method in config.methods:
            row = shown.get((scene.name, method.name))
            label = method.label or method.name
            if row is None:
                tiles.append((label + "\n(no run)", None))
            else:
                tiles.append((f"{label}\nMSE {fmt_value(row['mse'])}", os.path.join(out_dir, row["image"])))
        for j, (label, image_path) in enumerate(tiles):
            ax = axes[i][j]
            ax.set_xticks([])
            ax.set_yticks([])
            if image_path is not None:
                image = crop(read_pfm(image_path), scene.crop)
                ax.imshow(tonemap(image, scene.exposure), interpolation="nearest")
            ax.set_title(label, fontsize=8)
            if j == 0:
                ax.set_ylabel(scene.name, fontsize=9)
    where = "crop " + ",".join(map(str, config.scenes[0].crop)) if len(config.scenes) == 1 and config.scenes[0].crop \
        else "crops" if any(s.crop for s in config.scenes) else "full images"
    if budget is not None:
        fig.suptitle(f"{config.name}: {budget_caption(*budget)}, seed {seed}, {where}\n"
                     "same tone mapping for all; MSE over the whole image", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)


# ---------------------------------------------------------------------------------------------
# HTML


def html_table(config, table):
    """One table of build_tables() as HTML."""
    title, _metric, _budget, cells, best = table
    methods = [m.name for m in config.methods]
    out = [f"<h3>{html.escape(title)}</h3>", "<table>", "<tr><th>scene</th>" +
           "".join(f"<th>{html.escape(m)}</th>" for m in methods) + "</tr>"]
    for scene, row in cells.items():
        tds = []
        for method in methods:
            cell = row.get(method)
            text = cell_text(cell, False)
            tds.append(f"<td><b>{text}</b></td>" if best.get(scene) == method else f"<td>{text}</td>")
        out.append(f"<tr><th>{html.escape(scene)}</th>{''.join(tds)}</tr>")
    out.append("</table>")
    return "\n".join(out)


def write_html(config, tables, path, engine, rows=()):
    """report.html: plots, strip and tables in one page with relative links and inline CSS."""
    methods = "".join(f"<li><code>{html.escape(m.name)}</code>: <code>{html.escape(' '.join(m.args))}</code> "
                      f"(per-pixel budget as <code>{m.budget_flag}</code>)</li>" for m in config.methods)
    body = [
        f"<h1>Ablation: {html.escape(config.name)}</h1>",
        f"<p>{html.escape(config.description)}</p>" if config.description else "",
        f"<p>Engine: {html.escape(engine)}. {html.escape(reference_note(config, rows))} "
        f"Seeds: {', '.join(map(str, config.seeds))}. "
        "Metrics are <code>emlt compare --json --scene SCENE</code> on the saved images; "
        "cells are mean ± standard deviation over seeds, the best mean per scene in bold.</p>",
        "<p>Files: <a href=\"results.csv\">results.csv</a> (one row per run), "
        "<a href=\"table.md\">table.md</a>, <a href=\"runs/\">runs/</a>.</p>",
        "<h2>Convergence</h2>",
        "<img src=\"convergence.png\" alt=\"MSE against samples or mutations per pixel\">",
        "<img src=\"convergence_time.png\" alt=\"MSE against seconds\">",
        "<h2>Images</h2>", "<img src=\"strip.png\" alt=\"reference and each method's image\">",
        "<h2>Tables</h2>"] + [html_table(config, t) for t in tables] + [
        "<h2>Methods</h2>", f"<ul>{methods}</ul>",
        "<h2>Experiment file</h2>",
        f"<pre>{html.escape(json.dumps(config.raw, indent=2))}</pre>"]
    style = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
             "img{max-width:100%;display:block;margin:1em 0}table{border-collapse:collapse;margin:0.5em 0 1.5em}"
             "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}th{background:#f2f2f2}"
             "pre{background:#f6f6f6;padding:1em;overflow:auto}")
    with open(path, "w") as f:
        f.write("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">"
                f"<title>Ablation: {html.escape(config.name)}</title><style>{style}</style></head><body>\n"
                + "\n".join(b for b in body if b) + "\n</body></html>\n")


def write_report(config, rows, out_dir, engine, references, chains=()):
    """Write table.md, convergence.png, convergence_time.png, strip.png and report.html into out_dir."""
    tables = build_tables(config, rows) + build_chains_tables(config, chains)
    write_table_md(config, tables, os.path.join(out_dir, "table.md"), engine, rows)
    plot_convergence(config, rows, os.path.join(out_dir, "convergence.png"), "per_pixel")
    plot_convergence(config, rows, os.path.join(out_dir, "convergence_time.png"), "seconds")
    plot_strip(config, rows, out_dir, os.path.join(out_dir, "strip.png"), references)
    write_html(config, tables, os.path.join(out_dir, "report.html"), engine, rows)
