#!/usr/bin/python3
"""Draw the rayverify report plots from DIR/report.json into DIR/*.png.

Run by `rayverify audit --report DIR` and `rayverify bench --report DIR` with
Debian's /usr/bin/python3 (package python3-matplotlib). Prints "wrote NAME"
for every image written; each is written to a temporary name and renamed, so
a failure leaves no partial image. Plots whose data the report lacks (run time
in an audit report, the far-sphere sweep) are skipped.

  plot_report.py DIR --misclassifications NAMES --unscored NAMES
                 [--format png,svg,pdf] [--error-measure FIGURE:STATISTIC] [--points FILE]
  plot_report.py DIR --from-csv bench.csv [--format ...] [--error-measure ...] [--points FILE]

--format: the image formats, each plot once per format (default png).
--error-measure: the error the accuracy-against-time plot draws: an error
  figure of report.json (near_root_scaled_ulp, near_root_ulp,
  scale_error_radius, near_root_bits, ...) and max, p99 or median (default
  near_root_scaled_ulp:max, which a root exactly at 0 cannot blow up).
--from-csv: draw the accuracy-against-time plot from bench.csv (its "(all)"
  rows: time, misclassified and scored cases, error figures) instead of
  report.json, into DIR; the verdict lists are not needed.
--points: also write the accuracy-against-time plot's points as JSON.
"""
import argparse
import csv
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
# Variants not named above (the engine ports, robust_sphere.h, plugins): colours in order of
# appearance from Kelly's colours of maximum contrast, less white, black and the six closest to
# the colours above (orange, light blue, grey, pink, salmon, buff), then the Tableau 20 colours
# the table above leaves and five dark ones of Tableau 20b; beyond 25 they repeat.
EXTRA_COLOURS = ["#F3C300", "#875692", "#BE0032", "#008856", "#0067A5", "#604E97", "#F6A600", "#B3446C",
                 "#DCD300", "#882D17", "#8DB600", "#654522", "#E25822", "#2B3D26",
                 "#98df8a", "#c5b0d5", "#c49c94", "#7f7f7f", "#bcbd22", "#dbdb8d",
                 "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173"]


EXTRA_ASSIGNED = {}  # variant → colour from EXTRA_COLOURS, in order of first use


def colour(variant):
    if variant in VARIANT_COLOURS:
        return VARIANT_COLOURS[variant]
    return EXTRA_ASSIGNED.setdefault(variant, EXTRA_COLOURS[len(EXTRA_ASSIGNED) % len(EXTRA_COLOURS)])
# The case families' colours in the condition plot (matplotlib's tab10 then Dark2: distinct from each other).
FAMILY_COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
                  "#17becf", "#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02"]
PRECISION_MARKERS = {"float": "o", "double": "s", "long double": "D", "exact": "*"}
# The wrong-class and the unscored verdicts: rayverify passes them
# (--misclassifications, --unscored) from its one verdict table
# (src/compare/judge.cpp), so that this script keeps no list.
MISCLASS = ()
UNSCORED = ()
DPI = 100
plt.rcParams.update({"font.size": 11, "axes.titlesize": 11, "legend.fontsize": 10})


FORMATS = ("png",)  # --format


def save(fig, directory, name):
    """Writes NAME (a .png name) once per --format: NAME.png, NAME.svg, NAME.pdf."""
    stem = os.path.splitext(name)[0]
    for extension in FORMATS:
        written = stem + "." + extension
        path = os.path.join(directory, written)
        temporary = path + ".tmp." + extension
        fig.savefig(temporary, dpi=DPI, bbox_inches="tight", format=extension)
        os.replace(temporary, path)
        print("wrote " + written)
    plt.close(fig)


def number(x):
    if x is None:
        return None
    if isinstance(x, str):
        return math.inf if x == "inf" else (math.nan if x == "nan" else None)
    return float(x)


def scored(entry):
    v = entry["verdicts"]
    return entry["cases"] - sum(v.get(k, 0) for k in UNSCORED)


def misclassification_rate(entry):
    if "misclassified" in entry:  # read from bench.csv, which counts them
        return entry["misclassified"] / entry["cases_scored"] if entry["cases_scored"] else 0.0
    n = scored(entry)
    return sum(entry["verdicts"].get(k, 0) for k in MISCLASS) / n if n else 0.0


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


class LogAxis:
    """A log axis for values ≥ 0 that may be infinite: 0 on a labelled floor
    below 1 and below the smallest positive value, inf (and values beyond
    1e300) on a labelled ceiling a decade above the largest finite one."""

    def __init__(self, values, floor_label="0", ceiling_label="inf"):
        finite = [v for v in values if v is not None and math.isfinite(v) and 0 < v < 1e300]
        low = min(0, math.floor(math.log10(min(finite)))) if finite else -1
        high = math.ceil(math.log10(max(finite))) if finite else 1
        high = max(high, low + 1)
        self.step = max(1, math.ceil((high - low) / 8))
        # An exact answer is 0 ulp, a correctly rounded one at most 0.5: the floor sits below both.
        self.floor = 10.0 ** (low - max(1, self.step // 2))
        self.ceiling = 10.0 ** (high + 1)
        self.has_floor = any(v == 0 for v in values if v is not None)
        self.has_ceiling = any(v is not None and (not math.isfinite(v) or v >= 1e300) for v in values)
        self.floor_label, self.ceiling_label = floor_label, ceiling_label
        self.low, self.high = low, high

    def y(self, v):
        if v is None or not math.isfinite(v) or v >= 1e300:
            return self.ceiling
        return self.floor if v <= 0 else v

    def apply(self, ax):
        ax.set_yscale("log")
        ax.set_ylim(self.floor / 3 if self.has_floor else 10.0 ** self.low / 3,
                    self.ceiling * 3 if self.has_ceiling else 10.0 ** self.high * 3)
        exponents = range(self.low, self.high + 1, self.step)
        ticks = [10.0 ** e for e in exponents]
        labels = ["$10^{%d}$" % e for e in exponents]
        for shown, at, label in [(self.has_floor, self.floor, self.floor_label),
                                 (self.has_ceiling, self.ceiling, self.ceiling_label)]:
            if shown:
                ticks.append(at)
                labels.append(label)
                ax.axhline(at, color="grey", lw=0.8, ls=":", zorder=1)
        ax.set_yticks(ticks)
        ax.set_yticklabels(labels)
        ax.minorticks_off()


def measure_words(figure, statistic, precision_words):
    """The axis words for FIGURE:STATISTIC: its unit read from the figure's name."""
    if figure.endswith("_ulp"):
        unit = "ulp of " + precision_words
    elif figure.endswith("_bits"):
        unit = "bits"
    elif figure == "scale_error_radius":
        unit = "radii"
    else:
        unit = figure
    return "%s %s (%s)" % (statistic, figure, unit)


def plot_accuracy_vs_time(report, directory, measure=("near_root_scaled_ulp", "max"), points_file=None):
    figure, statistic = measure
    figures = sorted({k for _, _, e in accuracy_entries(report) for k, v in e.items() if isinstance(v, dict) and "count" in v})
    if figures and figure not in figures:
        sys.exit("plot_report.py: --error-measure: '%s' is not an error figure of this report (%s)"
                 % (figure, ", ".join(figures)))
    timing = {(r["variant"], r["precision"]): r["ns_per_test"] for r in report["timing"]["overall"]}
    entries = [(v, p, e) for v, p, e in accuracy_entries(report) if (v, p) in timing]
    exact = [(x, label, marker) for x, label, marker in
             [(timing.get(("exact_oracle", "exact")), "exact oracle (filtered)", "*"),
              (timing.get(("exact_reference", "exact")), "exact reference (no filter)", "P")] if x]
    # A float ulp is 2^29 double ulps: each precision has its own panel and front.
    # Long double roots are rounded to double and judged in double ulps.
    panels = [("float: " + measure_words(figure, statistic, "float"), ("float",), "ulp"),
              ("double and long double: " + measure_words(figure, statistic, "double"), ("double", "long double"),
               "ulp"),
              ("all precisions: misclassified share of scored cases", ("float", "double", "long double"), "rate")]
    drawn_points = []
    fig, axes = plt.subplots(1, 3, figsize=(18, 6.8))
    # The time axis fits the formulas; an exact oracle slower than all of them by more than its margin sits at
    # its right edge with its time written beside it.
    formula_times = [timing[(v, p)] for v, p, _ in entries]
    right_edge = max(formula_times) * 1.6 if formula_times else None
    for ax, (title, precisions, kind) in zip(axes, panels):
        chosen = [(v, p, e) for v, p, e in entries if p in precisions]
        rootless = sorted({v for v, p, e in chosen if kind == "ulp" and e.get(figure, {}).get("count", 0) == 0})
        chosen = [(v, p, e) for v, p, e in chosen if v not in rootless]
        if kind == "ulp":
            values = [number(e[figure].get(statistic)) for _, _, e in chosen]
            axis = LogAxis(values + [0.0], "0 (exact)", "inf")
        else:
            values = [misclassification_rate(e) for _, _, e in chosen]
            axis = LogAxis(values + [0.0], "0")
        points = []
        for (variant, precision, e), y in zip(chosen, values):
            x = timing[(variant, precision)]
            points.append((x, axis.y(y)))
            ax.scatter(x, axis.y(y), color=colour(variant), marker=PRECISION_MARKERS[precision],
                       s=70, edgecolors="black", linewidths=0.5, zorder=3)
            drawn_points.append({"panel": kind if kind == "rate" else precisions[0], "variant": variant,
                                 "precision": precision, "ns_per_test": x,
                                 "value": y if y is None or math.isfinite(y) else str(y)})
        # The exact answers cost time and have no error: on the floor.
        for x, label, marker in exact:
            points.append((x, axis.floor))
            beyond = right_edge is not None and x > right_edge
            drawn_at = right_edge / 1.15 if beyond else x
            ax.scatter(drawn_at, axis.floor, color="black", marker=marker, s=170, zorder=3)
            if beyond:
                ax.annotate("{:,.0f} ns →".format(x), (drawn_at, axis.floor), xytext=(10, 14),
                            textcoords="offset points", ha="right", fontsize=9)
        front = pareto(points)
        ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "k--", lw=1, zorder=2,
                label="Pareto front (time, error)")
        axis.apply(ax)
        ax.set_xscale("log")
        if right_edge is not None:
            ax.set_xlim(min(formula_times) / 1.6, right_edge)
        ax.set_xlabel("ns per ray–sphere test (CPU, median; log)")
        if rootless:
            ax.text(0.98, 0.87, "not drawn (no root returned):\n" + "\n".join(rootless), transform=ax.transAxes,
                    ha="right", va="top", fontsize=9, color="dimgrey")
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(loc="upper right")
    shown = list(dict.fromkeys(v for v, _, _ in entries))
    handles = [plt.Line2D([], [], color=colour(v), marker="o", ls="", ms=8, label=v) for v in shown]
    handles += [plt.Line2D([], [], color="grey", marker=PRECISION_MARKERS[p], ls="", ms=8, label=p)
                for p in ("float", "double", "long double")]
    handles += [plt.Line2D([], [], color="black", marker=marker, ls="", ms=12, label=label) for _, label, marker in exact]
    fig.legend(handles=handles, loc="upper center", ncol=6, bbox_to_anchor=(0.5, 0.0))
    fig.suptitle("Accuracy against run time (%s cases; lower left is better; %s over this finite corpus%s)"
                 % (report["corpus"]["cases"], statistic, ", not bounds" if statistic == "max" else ""))
    fig.tight_layout()
    save(fig, directory, "accuracy_vs_time.png")
    if points_file:
        with open(points_file, "w") as f:
            json.dump({"error_measure": figure + ":" + statistic, "points": drawn_points}, f, indent=1)


def report_from_csv(path):
    """The parts of report.json the accuracy-against-time plot reads, from bench.csv's "(all)" rows."""
    results, overall, cases = [], [], 0
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["family"] != "(all)":
                continue
            value = lambda column: None if row[column] == "" else float(row[column])  # noqa: E731
            overall.append({"variant": row["variant"], "precision": row["precision"],
                            "ns_per_test": value("ns_per_test_median")})
            cases = max(cases, int(row["cases_timed"]))
            if row["cases_scored"] == "":
                continue  # timed, not audited: an exact oracle
            entry = {"variant": row["variant"], "precision": row["precision"],
                     "cases_scored": int(row["cases_scored"]), "misclassified": int(row["misclassified"])}
            for column in row:
                if column.endswith("_count") and row[column] != "":
                    name = column[:-len("_count")]
                    entry[name] = {"count": int(row[column])}
                    for statistic in ("max", "p99", "median"):
                        if row.get(name + "_" + statistic, "") != "":
                            entry[name][statistic] = value(name + "_" + statistic)
            results.append(entry)
    return {"timing": {"overall": overall}, "results": results, "corpus": {"cases": cases}}


# A disagreement's marker in the condition plot: the two rounding causes apart, every cause by design as one.
CAUSE_MARKERS = {"conditioning_limited": "x", "algorithmic": "+", "by design": "d"}


def root_targets(points):
    """The targets with at least one nearest-root error (any-hit variants return no root)."""
    return [(label, t) for label, t in points["targets"].items() if any(u is not None for u in t["near_ulp"])]


def panel_grid(n, cols, width, height):
    rows = max(1, math.ceil(n / cols))
    cols = min(cols, n) if n else 1
    # One or two panels are drawn larger, so that the figure's title, legend and axis labels do not dwarf them.
    scale = {1: 2.0, 2: 1.5}.get(cols, 1.0)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols * scale, height * rows * scale), squeeze=False)
    for ax in axes.flat[n:]:
        ax.remove()
    return fig, axes


def plot_error_vs_condition(report, directory):
    points = report["case_points"]
    targets = root_targets(points)
    if not targets:
        return
    fig, axes = panel_grid(len(targets), 4, 4.2, 3.6)
    floor, top = 1e-3, 5e17
    # Disagreeing cases in a band above the errors, marked by their cause.
    band_at, band_from = 1e21, 10 ** 19.5
    # κ = ∞ is drawn at 10^21, in a strip from 10^19.5 to the axis's end.
    infinite_kappa_at, strip_from, x_end = 1e21, 10 ** 19.5, 1e22
    # Points coloured by the case's family, the same colour in every panel.
    families = list(dict.fromkeys(points["family"]))
    family_colour = {f: FAMILY_COLOURS[i % len(FAMILY_COLOURS)] for i, f in enumerate(families)}
    for ax, (label, t) in zip(axes.flat, targets):
        kappa = points["condition"]["float" if t["precision_of_inputs"] == "float" else "double"]
        causes = t.get("cause", [None] * len(kappa))
        drawn = {marker: ([], [], []) for marker in CAUSE_MARKERS.values()}
        agreeing = 0
        for k, u, f, v, cause in zip(kappa, t["near_ulp"], points["family"], t["verdict"], causes):
            k = number(k)
            if k is None or math.isnan(k):
                continue
            # κ = ∞ (a tangent's double root, or a root exactly 0: no relative error is small) in a strip of its own.
            x = infinite_kappa_at if math.isinf(k) else min(max(k, 1.0), top)
            if v == "agree":
                u = number(u)
                if u is None or math.isnan(u):
                    continue
                y = min(max(u, floor), top)  # an error of a root exactly 0 counts ulps of 0: often the ceiling
                agreeing += 1
                marker = "o"
            elif cause is not None:
                y, marker = band_at, CAUSE_MARKERS.get(cause, CAUSE_MARKERS["by design"])
            else:
                continue
            xs, ys, colours = drawn.setdefault(marker, ([], [], []))
            xs.append(x)
            ys.append(y)
            colours.append(family_colour[f])
        for marker, (xs, ys, colours) in drawn.items():
            if xs:
                ax.scatter(xs, ys, s=5 if marker == "o" else 14, alpha=0.5, color=colours, marker=marker,
                           linewidths=0.8)
        line = [1, 1e18]
        ax.plot(line, line, "k-", lw=1)
        ax.plot(line, [16 * x for x in line], "k:", lw=1)
        ax.axvspan(strip_from, x_end, color="0.92", zorder=0)
        ax.axhspan(band_from, 1e22, color="0.92", zorder=0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1, x_end)
        ax.set_ylim(floor / 3, 1e22)
        ax.set_xticks([1, 1e6, 1e12, 1e18, infinite_kappa_at])
        ax.set_xticklabels(["1", "$10^6$", "$10^{12}$", "$10^{18}$", "∞"])
        ax.set_yticks([floor, 1, 1e6, 1e12, top, band_at])
        ax.set_yticklabels(["0", "1", "$10^6$", "$10^{12}$", "≥5e17", "wrong"])
        ax.minorticks_off()
        ax.set_title("%s (%d agree)" % (label, agreeing))
        ax.grid(True, alpha=0.3)
    fig.supxlabel("κ, condition number of the nearest root (log)")
    fig.supylabel("nearest-root error, ulp (log)")
    # A relative error of κ·u is κ/2 to κ ulps (an ulp is u to 2u of the value): the line is drawn at κ ulps.
    handles = [plt.Line2D([], [], color="black", lw=1,
                          label="κ ulps (a relative error of κ·u, to a factor 2): what a backward-stable formula stays near"),
               plt.Line2D([], [], color="black", lw=1, ls=":", label="16·κ ulps")]
    handles += [plt.Line2D([], [], color="black", marker=m, ls="", ms=6, label="wrong: " + c.replace("_", " "))
                for c, m in CAUSE_MARKERS.items()]
    fig.legend(handles=handles, loc="upper center", ncol=3, bbox_to_anchor=(0.5, 0.985), frameon=False, fontsize=12)
    fig.legend(handles=[plt.Line2D([], [], color=family_colour[f], marker="o", ls="", ms=6, label=f) for f in families],
               loc="upper center", ncol=min(len(families), 8), bbox_to_anchor=(0.5, 0.0), frameon=False,
               title="the case's family")
    fig.suptitle("Error against condition number (the plot sample: agreeing cases by their error, wrong ones in the "
                 "top band by cause; the grey strip: κ = ∞, a tangent or a root exactly 0)", y=1.0)
    # Margins in inches, whatever the number of rows: the x label below, title and legend above.
    height = fig.get_figheight()
    fig.tight_layout(rect=(0.01, 0.35 / height, 1, 1 - 0.9 / height))
    save(fig, directory, "error_vs_condition.png")


# The distance/radius beyond which C = f·f − r² keeps no bit of r² in precision p: 2^(p/2)·r.
LOST_R2 = {"float": (2.0 ** 12, "4096·r"), "double": (2.0 ** 26.5, "$2^{26.5}$·r")}


def plot_far_sphere(report, directory):
    sweep = report.get("far_sphere_sweep")
    source = sweep["case_points"] if sweep else report["case_points"]
    what = sweep["description"] if sweep else "the far_sphere cases of this corpus's plot sample"
    ratio = source["distance_ratio"]
    keep = [i for i, f in enumerate(source["family"]) if (sweep or f == "far_sphere") and number(ratio[i])]
    if not keep:
        return
    # The forms that show the story (and any plugin); every audited variant when none of them was audited.
    present = list(dict.fromkeys(t["variant"] for t in source["targets"].values()))
    known = ["naive", "geometric", "stable_roots", "hearn_baker", "fma_discriminant"]
    variants = [v for v in present if v in known or v not in VARIANT_COLOURS] or present
    decades = sorted({math.floor(math.log10(number(ratio[i]))) for i in keep})
    bins = list(range(decades[0], decades[-1] + 1))
    names = ["$10^{%d}$–$10^{%d}$" % (d, d + 1) for d in bins]
    xs = list(range(len(bins)))
    # A share of 0 sits on a labelled floor a decade below the smallest nonzero share a bin can have.
    floor = 10.0 ** (math.floor(math.log10(1.0 / len(keep))) - 1)
    # A column per precision some shown variant runs in: a float-only target gets no empty double column.
    precisions = [p for p in ("float", "double") if any(v + "/" + p in source["targets"] for v in variants)]
    fig, axes = plt.subplots(3, len(precisions), figsize=(8 * len(precisions), 11), sharex=True, squeeze=False,
                             gridspec_kw={"height_ratios": [3, 3, 1.3]})

    def binned(variant, precision):
        """Per bin: the worst nearest-root error, the misclassified share and the scored cases; None if not run."""
        t = source["targets"].get(variant + "/" + precision)
        if not t:
            return None
        worst, rate, n = [], [], []
        for d in bins:
            idx = [i for i in keep if math.floor(math.log10(number(ratio[i]))) == d and t["verdict"][i] not in UNSCORED]
            errors = [number(t["near_ulp"][i]) for i in idx if t["near_ulp"][i] is not None]
            errors = [e for e in errors if math.isfinite(e)]
            worst.append(max(errors) if errors else None)
            rate.append(sum(1 for i in idx if t["verdict"][i] in MISCLASS) / len(idx) if idx else None)
            n.append(len(idx))
        return worst, rate, n

    lines = {(v, p): binned(v, p) for v in present for p in precisions}
    # An audited variant not drawn whose lines are a drawn one's, in every column, is named in that one's
    # label ("naive = half_b"); the others not drawn are listed under the legend.
    same_as = {v: [o for o in present if o not in variants
                   and all(lines[(o, p)] == lines[(v, p)] for p in precisions)] for v in variants}
    named = {o for others in same_as.values() for o in others}
    not_drawn = [v for v in present if v not in variants and v not in named]

    def label(variant):
        return " = ".join([variant] + same_as[variant])

    for column, precision in enumerate(precisions):
        counts, has_error = None, False
        for variant in variants:
            if lines[(variant, precision)] is None:
                continue
            worst, rate, n = lines[(variant, precision)]
            counts = counts or n
            has_error = has_error or any(w is not None for w in worst)
            # naive is drawn dashed on top: stable_roots and fma_discriminant share its C and often its line.
            style = dict(color=colour(variant), label=label(variant), ms=5, marker="o",
                         ls="--" if variant == "naive" else "-", lw=2.4 if variant == "naive" else 1.4,
                         zorder=4 if variant == "naive" else 3)
            axes[0][column].plot(xs, [w if w is None else max(w, 1e-3) for w in worst], **style)
            axes[1][column].plot(xs, [r if r is None else max(r, floor) for r in rate], **style)
        at, text = LOST_R2[precision]
        position = math.log10(at) - bins[0] - 0.5  # bins are centred on their index
        if -0.5 <= position <= len(bins) - 0.5:
            for row in (0, 1):
                axes[row][column].axvline(position, color="grey", ls="--", lw=1)
            right = position > len(bins) / 2
            axes[1][column].text(position, 0.55, (" %s: no bit of r² left in C = f·f − r² " % text),
                                 transform=axes[1][column].get_xaxis_transform(), va="center", fontsize=9,
                                 bbox=dict(facecolor="white", edgecolor="none", alpha=0.85),
                                 ha="right" if right else "left")
        if has_error:
            axes[0][column].set_yscale("log")
        else:
            axes[0][column].text(0.5, 0.5, "no root returned by these variants", ha="center",
                                 transform=axes[0][column].transAxes, color="dimgrey")
            axes[0][column].set_yticks([])
        axes[0][column].set_ylabel("max nearest-root error (ulp)")
        axes[0][column].set_title("%s: worst nearest-root error per bin (agreeing cases)" % precision)
        axes[1][column].set_yscale("log")
        axes[1][column].set_ylim(floor / 2, 1.5)
        decades = range(round(math.log10(floor)) + 1, 1)
        axes[1][column].set_yticks([floor] + [10.0 ** e for e in decades])
        axes[1][column].set_yticklabels(["0"] + ["%g" % 10.0 ** e for e in decades])
        axes[1][column].minorticks_off()
        axes[1][column].set_ylabel("misclassified / scored")
        axes[1][column].set_title("%s: misclassified share per bin" % precision)
        bars = axes[2][column].bar(xs, counts or [0] * len(xs), color="lightgrey", edgecolor="grey")
        axes[2][column].bar_label(bars, fontsize=9)
        axes[2][column].set_ylabel("cases")
        axes[2][column].set_ylim(0, max(counts or [1]) * 1.35)
        axes[2][column].set_xticks(xs)
        axes[2][column].set_xticklabels(names)
        axes[2][column].set_xlabel("distance / radius  |o − c| / r  (one bin per decade)")
        for row in (0, 1):
            axes[row][column].grid(True, alpha=0.3)
    shown = [v for v in variants if any(v + "/" + p in source["targets"] for p in ("float", "double"))]
    fig.legend(handles=[plt.Line2D([], [], color=colour(v), marker="o", ls="--" if v == "naive" else "-",
                                   lw=2.4 if v == "naive" else 1.4, label=label(v)) for v in shown],
               loc="upper center", ncol=min(len(shown), 9), bbox_to_anchor=(0.5, 0.965), frameon=False)
    if not_drawn:
        fig.text(0.5, -0.005, "audited, not drawn: " + ", ".join(not_drawn), ha="center", va="top", fontsize=9,
                 color="dimgrey", wrap=True)
    fig.suptitle("Far spheres (Ray Tracing Gems ch. 7): " + what, fontsize=11)
    # Room above the panels for the legend's rows (nine entries a row).
    legend_rows = (len(shown) + 8) // 9
    fig.tight_layout(rect=(0, 0, 1, 0.955 - 0.025 * legend_rows))
    save(fig, directory, "far_sphere.png")


def plot_histograms(report, directory):
    points = report["case_points"]
    targets = root_targets(points)
    if not targets:
        return
    # x is log10 of the error: a bar of its own for exactly 0 (at -4) and for
    # 1e20 and beyond, infinity included (at 21); half-decade bins between.
    zero_at, beyond_at = -4.0, 21.0
    edges = [zero_at - 0.25, zero_at + 0.25] + [e / 2 for e in range(-6, 41)] + [beyond_at - 0.25, beyond_at + 0.25]
    fig, axes = panel_grid(len(targets), 4, 4.2, 3.0)
    top = 1
    for ax, (label, t) in zip(axes.flat, targets):
        values = [number(u) for u in t["near_ulp"] if u is not None]
        xs = []
        for v in values:
            if v == 0:
                xs.append(zero_at)
            elif not math.isfinite(v) or v >= 1e20:
                xs.append(beyond_at)
            else:
                xs.append(min(max(math.log10(v), -3.0), 19.99))
        # One filled outline per panel, not a patch per bin: the same pixels (on the shipped corpus's report,
        # the same bytes), and the figure's three drawings (layout, tight bounding box, image) take a fraction
        # of the time.
        counts, _, _ = ax.hist(xs, bins=edges, color=colour(t["variant"]), histtype="stepfilled")
        top = max(top, max(counts))
        ax.axvline(math.log10(0.5), color="black", lw=0.8, ls=":")
        ax.set_title("%s (%d cases)" % (label, len(values)))
        ax.grid(True, alpha=0.3)
    for ax in axes.flat[:len(targets)]:
        ax.set_yscale("log")
        ax.set_ylim(0.7, top * 2)
        ax.set_xlim(zero_at - 0.6, beyond_at + 0.6)
        ax.set_xticks([zero_at, 0, 5, 10, 15, beyond_at])
        ax.set_xticklabels(["0", "1", "$10^5$", "$10^{10}$", "$10^{15}$", "≥1e20"])
        ax.minorticks_off()
    fig.supxlabel("nearest-root error, ulp (log; half-decade bins; own bars for 0 and for ≥ 1e20 or inf)")
    fig.supylabel("cases (log)")
    fig.suptitle("Nearest-root ULP error per variant: agreeing cases of the plot sample "
                 "(dotted: 0.5 ulp, correctly rounded)")
    fig.tight_layout(rect=(0, 0, 1, 0.985))
    save(fig, directory, "ulp_histograms.png")


def plot_builds(report, directory):
    """builds.png: each build's verdict shares (`rayverify builds`), one bar per build and precision."""
    builds = report["builds"]
    order = [r["name"] for r in builds["rows"] if r["status"] == "ran"]
    entries = [r for name in order for r in report.get("results", []) if r["variant"] == name]
    if not entries:
        return
    kinds = []
    for e in entries:
        for k, n in e["verdicts"].items():
            if n and k not in kinds and k not in UNSCORED:
                kinds.append(k)
    palette = ["#2ca02c", "#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
               "#1f77b4", "#aec7e8", "#ffbb78", "#98df8a"]
    fig, ax = plt.subplots(figsize=(9, 0.32 * len(entries) + 1.6))
    labels = ["%s/%s%s" % (e["variant"], e["precision"], " (reference)" if e["variant"] == builds.get("reference") else "")
              for e in entries]
    left = [0.0] * len(entries)
    for i, k in enumerate(kinds):
        widths = [(e["verdicts"].get(k, 0) / scored(e) if scored(e) else 0.0) for e in entries]
        colour_of = "#2ca02c" if k == "agree" else palette[1 + (i % (len(palette) - 1))]
        ax.barh(range(len(entries)), widths, left=left, color=colour_of, label=k)
        left = [a + b for a, b in zip(left, widths)]
    ax.set_yticks(range(len(entries)))
    ax.set_yticklabels(labels, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(0, 1)
    ax.set_xlabel("share of the scored cases")
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8)
    ax.set_title("Verdicts per build (rayverify builds; %d cases, reference %s)" % (builds["cases"], builds.get("reference")))
    fig.tight_layout()
    save(fig, directory, "builds.png")


def main():
    global MISCLASS, UNSCORED, FORMATS
    parser = argparse.ArgumentParser(description="Draw the rayverify report plots.")
    parser.add_argument("directory")
    parser.add_argument("--misclassifications", default="", help="the wrong-class verdicts (not with --from-csv)")
    parser.add_argument("--unscored", default="", help="the verdicts not scored (not with --from-csv)")
    parser.add_argument("--format", default="png")
    parser.add_argument("--error-measure", default="near_root_scaled_ulp:max")
    parser.add_argument("--from-csv")
    parser.add_argument("--points")
    args = parser.parse_args()
    MISCLASS = tuple(v for v in args.misclassifications.split(",") if v)
    UNSCORED = tuple(v for v in args.unscored.split(",") if v)
    if not args.from_csv and not (MISCLASS and UNSCORED):
        sys.exit("plot_report.py: --misclassifications and --unscored are needed to draw from report.json")
    FORMATS = tuple(args.format.split(","))
    for extension in FORMATS:
        if extension not in ("png", "svg", "pdf"):
            sys.exit("plot_report.py: --format: '%s' is not png, svg or pdf" % extension)
    figure, _, statistic = args.error_measure.partition(":")
    if statistic not in ("max", "p99", "median"):
        sys.exit("plot_report.py: --error-measure: '%s' is not FIGURE:max, FIGURE:p99 or FIGURE:median"
                 % args.error_measure)
    measure = (figure, statistic)
    directory = args.directory
    if args.from_csv:
        plot_accuracy_vs_time(report_from_csv(args.from_csv), directory, measure, args.points)
        return
    with open(os.path.join(directory, "report.json")) as f:
        report = json.load(f)
    if "timing" in report:
        plot_accuracy_vs_time(report, directory, measure, args.points)
    if "builds" in report:
        plot_builds(report, directory)
    if "case_points" in report:
        plot_error_vs_condition(report, directory)
        plot_far_sphere(report, directory)
        plot_histograms(report, directory)


if __name__ == "__main__":
    main()
