#!/usr/bin/python3
"""Draws a gvs eval plot: estimate vs truth over time (direction, speed with
the estimate's quality, yaw rate) above their error histograms, legends
above the panels, and why speeds are missing below them. Called by
`gvs eval --plot`; runs on Debian's python3-matplotlib under /usr/bin/python3.

usage: gvs_plot.py JOINED.csv OUT.png TITLE [--speed-note TEXT] [--describe]

JOINED.csv: t_s,truth_speed_mps,truth_direction_deg,truth_yaw_rate_dps,
speed_mps,direction_deg,yaw_rate_dps,quality (empty = no estimate).
--speed-note: why moving frames have no speed (gvs eval's text), printed
under the panels. --describe: also print the figure's panels and legends
as JSON on standard output (what the tests check).
"""
import argparse
import csv
import json
import math
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MOVING_KMH = 0.5  # gvs eval's "moving": below it direction and % speed errors mean nothing


def num(text):
    return float(text) if text not in ("", None) else math.nan


def wrap(deg):
    return (deg + 180.0) % 360.0 - 180.0


def read(joined):
    with open(joined, newline="") as f:
        rows = list(csv.DictReader(f))
    col = {k: [num(r[k]) for r in rows] for k in rows[0].keys()} if rows else {}
    t = col.get("t_s", [])
    return {
        "t": t,
        "truth_kmh": [v * 3.6 for v in col.get("truth_speed_mps", [])],
        "truth_dir": col.get("truth_direction_deg", []),
        "truth_yaw": col.get("truth_yaw_rate_dps", []),
        "kmh": [v * 3.6 for v in col.get("speed_mps", [])],
        "dir": col.get("direction_deg", []),
        "yaw": col.get("yaw_rate_dps", []),
        "quality": col.get("quality", []),
    }


def series(a, t, truth, estimate, colour, ylabel):
    a.plot(t, truth, "k-", lw=1.2, label="truth")
    a.plot(t, estimate, ".", ms=2.5, color=colour, label="estimate")
    a.set_xlabel("time (s)")
    a.set_ylabel(ylabel)
    a.grid(alpha=0.3)


def legend_above(a, handles=None):
    """The legend in a row above the panel, outside the data."""
    kw = {"handles": handles} if handles else {}
    a.legend(loc="lower left", bbox_to_anchor=(0.0, 1.01), ncol=3, fontsize=8, frameon=False,
              borderaxespad=0.0, **kw)


def hist(a, data, label, unit, empty_text):
    if data:
        rms = math.sqrt(sum(x * x for x in data) / len(data))
        a.hist(data, bins=60, color="gray")
        a.set_title("%s error: n=%d, RMS %.3f %s, max |e| %.3f %s"
                    % (label, len(data), rms, unit, max(abs(x) for x in data), unit), fontsize=9)
    else:
        a.set_title("%s error: no data" % label, fontsize=9)
        a.text(0.5, 0.5, empty_text, transform=a.transAxes, ha="center", va="center", fontsize=10, color="tab:red")
        a.set_xticks([])
        a.set_yticks([])
    a.set_xlabel("%s error (%s)" % (label, unit))
    a.set_ylabel("frames")


def draw(d, title, speed_note):
    t = d["t"]
    moving = [s >= MOVING_KMH for s in d["truth_kmh"]]
    dir_err = [wrap(e - tr) for e, tr, m in zip(d["dir"], d["truth_dir"], moving)
               if m and not math.isnan(e) and not math.isnan(tr)]
    spd_err = [(e - tr) / tr * 100.0 for e, tr, m in zip(d["kmh"], d["truth_kmh"], moving)
               if m and not math.isnan(e)]
    yaw_err = [e - tr for e, tr in zip(d["yaw"], d["truth_yaw"])
               if not math.isnan(e) and not math.isnan(tr)]
    note_lines = []
    for line in (speed_note or "").strip().splitlines():
        note_lines += textwrap.wrap(line, 190, subsequent_indent="      ") or [""]

    fig, ax = plt.subplots(2, 3, figsize=(17, 8.5 + 0.17 * len(note_lines)))
    fig.suptitle(title)

    a = ax[0][0]
    series(a, t, d["truth_dir"], d["dir"], "tab:red", "direction (deg)")
    legend_above(a)

    a = ax[0][1]
    series(a, t, d["truth_kmh"], d["kmh"], "tab:blue", "speed (km/h)")
    a2 = a.twinx()
    (q,) = a2.plot(t, d["quality"], "-", lw=0.6, color="tab:green", alpha=0.5, label="quality")
    a2.set_ylim(0, 1.05)
    a2.set_ylabel("quality", color="tab:green")
    legend_above(a, a.get_legend_handles_labels()[0] + [q])

    a = ax[0][2]
    series(a, t, d["truth_yaw"], d["yaw"], "tab:purple", "yaw rate (deg/s)")
    legend_above(a)

    no_speed = "no speed on any moving frame:\nwhy is written below" if speed_note else "no speed estimates"
    hist(ax[1][0], dir_err, "direction", "deg", "no direction estimates")
    hist(ax[1][1], spd_err, "speed", "%", no_speed)
    hist(ax[1][2], yaw_err, "yaw rate", "deg/s", "no yaw-rate estimates\n(the method measured none)")

    bottom = 0.0
    if note_lines:
        bottom = min(0.4, (0.25 + 0.17 * len(note_lines)) / fig.get_figheight())
        fig.text(0.01, 0.005, "\n".join(note_lines), fontsize=8, family="monospace", va="bottom", ha="left",
                 color="tab:red", gid="speed-note")
    fig.tight_layout(rect=(0.0, bottom, 1.0, 1.0))
    return fig


def describe(fig):
    """Panels, their series and legends, and whether any legend covers a panel."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    axes = fig.get_axes()
    panels = []
    for a in axes:
        legend = a.get_legend()
        covers = False
        if legend is not None:
            box = legend.get_window_extent(renderer)
            covers = any(box.overlaps(b.get_window_extent(renderer)) for b in axes)
        panels.append({
            "ylabel": a.get_ylabel(),
            "title": a.get_title(),
            "lines": [{"label": ln.get_label(),
                       "points": sum(1 for y in ln.get_ydata() if not math.isnan(y))} for ln in a.get_lines()],
            "legend": [tx.get_text() for tx in legend.get_texts()] if legend else [],
            "legend_covers_a_panel": covers,
        })
    return {"panels": panels, "speed_note": "\n".join(tx.get_text() for tx in fig.texts if tx.get_gid() == "speed-note")}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("joined")
    p.add_argument("out_png")
    p.add_argument("title")
    p.add_argument("--speed-note", default="")
    p.add_argument("--describe", action="store_true")
    args = p.parse_args()
    fig = draw(read(args.joined), args.title, args.speed_note)
    fig.savefig(args.out_png, dpi=90, format="png")  # the path as given, whatever its suffix
    if args.describe:
        print(json.dumps(describe(fig), indent=1))


if __name__ == "__main__":
    main()
