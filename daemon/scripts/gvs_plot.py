#!/usr/bin/python3
"""Draws a gvs eval plot: estimate vs truth over time (direction, speed) and
error histograms. Called by `gvs eval --plot`; runs on Debian's
python3-matplotlib and python3-numpy under /usr/bin/python3.

usage: gvs_plot.py JOINED.csv OUT.png TITLE
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(text):
    return float(text) if text not in ("", None) else math.nan


def wrap(deg):
    return (deg + 180.0) % 360.0 - 180.0


def main(joined, out_png, title):
    rows = list(csv.DictReader(open(joined, newline="")))
    t = [num(r["t_s"]) for r in rows]
    ts = [num(r["truth_speed_mps"]) * 3.6 for r in rows]
    td = [num(r["truth_direction_deg"]) for r in rows]
    es = [num(r["speed_mps"]) * 3.6 for r in rows]
    ed = [num(r["direction_deg"]) for r in rows]
    q = [num(r["quality"]) for r in rows]

    dir_err = [wrap(e - tr) for e, tr, s in zip(ed, td, ts)
               if not math.isnan(e) and not math.isnan(tr) and s >= 0.5]
    spd_err = [(e - tr) / tr * 100.0 for e, tr in zip(es, ts)
               if not math.isnan(e) and tr >= 0.5]

    fig, ax = plt.subplots(2, 2, figsize=(13, 8))
    fig.suptitle(title)
    a = ax[0][0]
    a.plot(t, td, "k-", lw=1.2, label="truth")
    a.plot(t, ed, ".", ms=2.5, color="tab:red", label="estimate")
    a.set_xlabel("time (s)")
    a.set_ylabel("direction (deg)")
    a.legend(loc="best")
    a.grid(alpha=0.3)

    a = ax[0][1]
    a.plot(t, ts, "k-", lw=1.2, label="truth")
    a.plot(t, es, ".", ms=2.5, color="tab:blue", label="estimate")
    a2 = a.twinx()
    a2.plot(t, q, "-", lw=0.6, color="tab:green", alpha=0.5)
    a2.set_ylim(0, 1.05)
    a2.set_ylabel("quality", color="tab:green")
    a.set_xlabel("time (s)")
    a.set_ylabel("speed (km/h)")
    a.legend(loc="upper left")
    a.grid(alpha=0.3)

    def hist(a, data, label, unit):
        if data:
            rms = math.sqrt(sum(x * x for x in data) / len(data))
            a.hist(data, bins=60, color="gray")
            a.set_title("%s error: n=%d, RMS %.3f %s, max |e| %.3f %s"
                        % (label, len(data), rms, unit, max(abs(x) for x in data), unit), fontsize=9)
        else:
            a.set_title("%s error: no estimates" % label, fontsize=9)
        a.set_xlabel("%s error (%s)" % (label, unit))
        a.set_ylabel("frames")

    hist(ax[1][0], dir_err, "direction", "deg")
    hist(ax[1][1], spd_err, "speed", "%")
    fig.tight_layout()
    fig.savefig(out_png, dpi=90)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3])
