#!/usr/bin/python3
"""Draw the rayverify report plots from DIR/report.json into DIR/*.png.

Run by `rayverify audit --report DIR` and `rayverify bench --report DIR` with
Debian's /usr/bin/python3 (package python3-matplotlib). Prints "wrote NAME"
for every PNG written; each is written to NAME.tmp.png and renamed, so a
failure leaves no partial image. Plots whose data the report lacks (run time
in an audit report, the far-sphere sweep) are skipped.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

VARIANT_COLOURS = {
    "naive": "#1f77b4", "half_b": "#aec7e8", "seed003_reduced": "#ff7f0e", "seed004_early_out": "#ffbb78",
    "geometric": "#2ca02c", "stable_roots": "#9467bd", "hearn_baker": "#d62728", "fma_discriminant": "#8c564b",
    "hearn_baker_unit": "#e377c2", "hearn_baker_nearest": "#ff9896", "hearn_baker_unit_nearest": "#f7b6d2",
    "hearn_baker_any_hit": "#17becf", "hearn_baker_unit_any_hit": "#9edae5",
    "exact_oracle": "#000000",
}
# Variants not named above (plugins, new variants): colours from a second palette, in order of appearance.
EXTRA_COLOURS = ["#bcbd22", "#7f7f7f", "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173", "#3182bd"]


EXTRA_ASSIGNED = {}  # variant → colour from EXTRA_COLOURS, in order of first use


def colour(variant):
    if variant in VARIANT_COLOURS:
        return VARIANT_COLOURS[variant]
    return EXTRA_ASSIGNED.setdefault(variant, EXTRA_COLOURS[len(EXTRA_ASSIGNED) % len(EXTRA_COLOURS)])
PRECISION_MARKERS = {"float": "o", "double": "s", "long double": "D", "exact": "*"}
MISCLASS = ("false_miss", "false_hit", "tangent_split", "tangent_missed", "false_tangent")
FLOOR = 1e-3  # where zero errors are drawn on log axes


def save(fig, directory, name):
    path = os.path.join(directory, name)
    temporary = path + ".tmp.png"
    fig.savefig(temporary, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(temporary, path)
    print("wrote " + name)


def number(x):
    if x is None:
        return None
    if isinstance(x, str):
        return math.inf if x == "inf" else (math.nan if x == "nan" else None)
    return float(x)


def scored(entry):
    v = entry["verdicts"]
    return entry["cases"] - v["invalid"] - v["contract_violation"]


def misclassification_rate(entry):
    n = scored(entry)
    return sum(entry["verdicts"][k] for k in MISCLASS) / n if n else 0.0


def accuracy_entries(report):
    """(variant, precision, entry) for float, double and long double."""
    out = [(r["variant"], r["precision"], r) for r in report.get("results", [])]
    out += [(r["variant"], "long double", r) for r in report.get("long_double", {}).get("results", [])]
    return out


def pareto(points):
    """Indices of the points not dominated in (x, y), both minimised."""
    front = []
    for i, (x, y) in enumerate(points):
        if not any((x2 <= x and y2 <= y) and (x2 < x or y2 < y) for j, (x2, y2) in enumerate(points) if j != i):
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def plot_accuracy_vs_time(report, directory):
    timing = {(r["variant"], r["precision"]): r["ns_per_test"] for r in report["timing"]["overall"]}
    entries = [(v, p, e) for v, p, e in accuracy_entries(report) if (v, p) in timing]
    oracle = timing.get(("exact_oracle", "exact"))
    reference = timing.get(("exact_reference", "exact"))
    metrics = [("max ulp error (nearest root)", lambda e: number(e["near_root_ulp"].get("max"))),
               ("p99 ulp error (nearest root)", lambda e: number(e["near_root_ulp"].get("p99"))),
               ("misclassification rate", misclassification_rate)]
    fig, axes = plt.subplots(1, 3, figsize=(17, 6))
    for ax, (title, metric) in zip(axes, metrics):
        finite = [metric(e) for _, _, e in entries if metric(e) is not None and math.isfinite(metric(e)) and metric(e) > 0]
        # Infinite (and beyond 1e300) errors are drawn on a line above the largest finite one.
        finite = [y for y in finite if y < 1e300]
        top = 10 ** (math.ceil(math.log10(max(finite))) + 1) if finite else 10
        points = []
        for variant, precision, e in entries:
            y = metric(e)
            y = top if (y is None or not math.isfinite(y) or y >= top) else max(y, FLOOR)
            x = timing[(variant, precision)]
            points.append((x, y))
            ax.scatter(x, y, color=colour(variant), marker=PRECISION_MARKERS[precision],
                       s=60, edgecolors="black", linewidths=0.5, zorder=3)
        # The exact answers cost time and have no error: drawn on the floor line.
        for x, label, marker, offset in [(oracle, "exact oracle (filtered)", "*", (-10, 10)),
                                         (reference, "exact reference (no filter)", "P", (-10, -16))]:
            if not x:
                continue
            points.append((x, FLOOR))
            ax.scatter(x, FLOOR, color="black", marker=marker, s=160, zorder=3)
            ax.annotate(label, (x, FLOOR), textcoords="offset points", xytext=offset, ha="right", fontsize=8)
        front = pareto(points)
        ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "k--", lw=1, zorder=2,
                label="Pareto front")
        if any(y == top for _, y in points):
            ax.axhline(top, color="grey", lw=0.5, ls=":")
            ax.text(min(p[0] for p in points), top, " inf or > 1e300", va="bottom", fontsize=8, color="grey")
        ax.axhline(FLOOR, color="grey", lw=0.5, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("run time: ns per ray–sphere test (CPU, median; log)")
        ax.set_ylabel(title + " (log; 0 drawn at 1e-3)")
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    shown = list(dict.fromkeys(v for v, _, _ in entries))  # the report's variants, in its order
    variant_handles = [plt.Line2D([], [], color=colour(v), marker="o", ls="", label=v) for v in shown]
    precision_handles = [plt.Line2D([], [], color="grey", marker=m, ls="", label=p) for p, m in PRECISION_MARKERS.items()]
    fig.legend(handles=variant_handles + precision_handles, loc="lower center", ncol=6, fontsize=9,
               bbox_to_anchor=(0.5, -0.12))
    fig.suptitle("Accuracy against run time (%s cases; maxima over this finite corpus, not bounds)"
                 % report["corpus"]["cases"])
    fig.tight_layout()
    save(fig, directory, "accuracy_vs_time.png")


def target_columns(points):
    return list(points["targets"].items())


def plot_error_vs_condition(report, directory):
    points = report["case_points"]
    targets = target_columns(points)
    n = len(targets)
    cols = 4
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), sharex=True, sharey=True, squeeze=False)
    for ax, (label, t) in zip(axes.flat, targets):
        kappa = points["condition"]["float" if t["precision_of_inputs"] == "float" else "double"]
        xs, ys = [], []
        for k, u in zip(kappa, t["near_ulp"]):
            k, u = number(k), number(u)
            if k is None or u is None or not math.isfinite(k) or not math.isfinite(u):
                continue
            xs.append(min(max(k, 1.0), 5e17))
            ys.append(min(max(u, FLOOR), 5e17))
        ax.scatter(xs, ys, s=4, alpha=0.4, color=colour(t["variant"]))
        line = [1, 1e18]
        ax.plot(line, line, "k-", lw=1, label="κ·u (in ulps: κ)")
        ax.plot(line, [16 * x for x in line], "k:", lw=1, label="16·κ·u")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1, 1e18)
        ax.set_ylim(FLOOR / 2, 1e18)
        ax.set_title(label, fontsize=10)
        ax.grid(True, alpha=0.3)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("κ of the near root")
    for ax in axes[:, 0]:
        ax.set_ylabel("near-root error (ulp)")
    axes.flat[0].legend(loc="upper left", fontsize=8)
    fig.suptitle("Error against condition number (agreeing cases with finite κ; 0 ulp drawn at 1e-3, "
                 "values above 5e17 on the top edge)")
    fig.tight_layout(rect=(0, 0, 1, 0.98))
    save(fig, directory, "error_vs_condition.png")


def plot_far_sphere(report, directory):
    sweep = report.get("far_sphere_sweep")
    source = sweep["case_points"] if sweep else report["case_points"]
    what = sweep["description"] if sweep else "far_sphere cases of this corpus"
    ratio = source["distance_ratio"]
    keep = [i for i, f in enumerate(source["family"]) if sweep or f == "far_sphere"]
    if not keep:
        return
    shown = ["naive", "geometric", "stable_roots", "hearn_baker", "fma_discriminant"]
    edges = [10 ** (1 + 0.25 * i) for i in range(0, 33)]
    fig, axes = plt.subplots(2, 2, figsize=(15, 9), sharex=True)
    for column, precision in enumerate(["float", "double"]):
        for variant in shown:
            t = source["targets"].get(variant + "/" + precision)
            if not t:
                continue
            centres, worst, rate = [], [], []
            for lo, hi in zip(edges, edges[1:]):
                idx = [i for i in keep if ratio[i] is not None and lo <= number(ratio[i]) < hi
                       and t["verdict"][i] not in ("invalid", "contract_violation")]
                if not idx:
                    continue
                errors = [number(t["near_ulp"][i]) for i in idx if t["near_ulp"][i] is not None]
                wrong = sum(1 for i in idx if t["verdict"][i] in MISCLASS)
                centres.append(math.sqrt(lo * hi))
                worst.append(max([max(e, FLOOR) for e in errors if math.isfinite(e)] or [math.nan]))
                rate.append(wrong / len(idx))
            # naive is drawn dashed on top: stable_roots and fma_discriminant share its C and often its line.
            style = dict(color=colour(variant), label=variant, ms=3,
                         ls="--" if variant == "naive" else "-", lw=2.2 if variant == "naive" else 1.2,
                         zorder=4 if variant == "naive" else 3, marker="o")
            axes[0][column].plot(centres, worst, **style)
            axes[1][column].plot(centres, [max(r, FLOOR) for r in rate], **style)
        for row in (0, 1):
            ax = axes[row][column]
            ax.axvline(4096, color="grey", ls="--", lw=1)
            ax.text(4096, 0.98, " 4096·r", transform=ax.get_xaxis_transform(), va="top", fontsize=9)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, alpha=0.3)
        axes[0][column].set_title("%s: worst near-root error per bin (agreeing cases)" % precision)
        axes[1][column].set_title("%s: misclassified fraction per bin (0 drawn at 1e-3)" % precision)
        axes[0][column].set_ylabel("max near-root error (ulp)")
        axes[1][column].set_ylabel("misclassified / scored")
        axes[1][column].set_xlabel("distance / radius  |o − c| / r")
        axes[0][column].legend(loc="upper left", fontsize=8)
    fig.suptitle("Far spheres (RTG ch.7): " + what, fontsize=10)
    fig.tight_layout()
    save(fig, directory, "far_sphere.png")


def plot_histograms(report, directory):
    points = report["case_points"]
    targets = target_columns(points)
    n = len(targets)
    cols = 4
    rows = math.ceil(n / cols)
    edges = [0] + [10 ** (e / 2) for e in range(-6, 41)]
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.0 * rows), sharex=True, sharey=True, squeeze=False)
    for ax, (label, t) in zip(axes.flat, targets):
        values = [number(u) for u in t["near_ulp"] if u is not None]
        values = [min(max(v, 1.5e-3), 9e19) if math.isfinite(v) else 9e19 for v in values]
        ax.hist(values, bins=[1e-3] + edges[1:], color=colour(t["variant"]))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axvline(0.5, color="black", lw=0.8, ls=":")
        ax.set_title(label, fontsize=10)
        ax.grid(True, alpha=0.3)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("near-root error (ulp; 0 in the first bin, > 1e19 and inf in the last)")
    for ax in axes[:, 0]:
        ax.set_ylabel("cases")
    fig.suptitle("Near-root ULP error per variant (agreeing cases; dotted: 0.5 ulp, correctly rounded)")
    fig.tight_layout(rect=(0, 0, 1, 0.98))
    save(fig, directory, "ulp_histograms.png")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_report.py REPORT_DIR")
    directory = sys.argv[1]
    with open(os.path.join(directory, "report.json")) as f:
        report = json.load(f)
    if "timing" in report:
        plot_accuracy_vs_time(report, directory)
    if "case_points" in report:
        plot_error_vs_condition(report, directory)
        plot_far_sphere(report, directory)
        plot_histograms(report, directory)


if __name__ == "__main__":
    main()
