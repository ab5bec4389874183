"""Summary, text and HTML (inline SVG) report of a penumbra_load.py run."""
import html as htmllib


def percentile(sorted_values, q):
    if not sorted_values:
        return float("nan")
    k = min(len(sorted_values) - 1, max(0, int(round(q * (len(sorted_values) - 1)))))
    return sorted_values[k]


def summarize(samples, rss, streams, args):
    """samples: (endpoint, start s, seconds, status); status -1 timeout, -2 connection error."""
    per = {}
    for endpoint, _, seconds, status in samples:
        per.setdefault(endpoint, []).append((seconds, status))
    endpoints = {}
    for endpoint, rows in sorted(per.items()):
        ok = sorted(s for s, st in rows if 200 <= st < 300)
        endpoints[endpoint] = {
            "count": len(rows), "ok": len(ok),
            "busy_503": sum(1 for _, st in rows if st == 503),
            "statuses": {str(st): sum(1 for _, x in rows if x == st) for st in sorted({x for _, x in rows})},
            "errors": sum(1 for _, st in rows if st >= 400 and st != 503 or st == -2),
            "timeouts": sum(1 for _, st in rows if st == -1),
            "p50_ms": 1e3 * percentile(ok, 0.50), "p95_ms": 1e3 * percentile(ok, 0.95),
            "p99_ms": 1e3 * percentile(ok, 0.99), "max_ms": 1e3 * (ok[-1] if ok else float("nan")),
        }
    gets = sorted(s for e, _, s, st in samples if e != "edit" and 200 <= st < 300)
    summary = {
        "config": {"clients": args.clients, "scenes": args.scenes, "seconds": args.seconds,
                   "mode": args.mode, "edit_rate": args.edit_rate, "events": args.events},
        "requests": len(samples),
        "throughput_rps": len(samples) / args.seconds,
        "edits_ok": endpoints.get("edit", {}).get("ok", 0),
        "edits_per_s": endpoints.get("edit", {}).get("ok", 0) / args.seconds,
        "errors": sum(e["errors"] for e in endpoints.values()) + streams["errors"],
        "timeouts": sum(e["timeouts"] for e in endpoints.values()),
        "busy_503": sum(e["busy_503"] for e in endpoints.values()),
        "get_p99_ms": 1e3 * percentile(gets, 0.99),
        "endpoints": endpoints, "events": streams,
    }
    if rss:
        after = [r for r in rss if r[0] >= args.warmup] or rss
        summary.update({"rss_start_mb": rss[0][1], "rss_baseline_mb": after[0][1],
                        "rss_end_mb": rss[-1][1], "rss_max_mb": max(r[1] for r in rss),
                        "rss_growth_mb": rss[-1][1] - after[0][1],
                        "threads_max": max(r[2] for r in rss)})
    return summary


def text(s):
    c = s["config"]
    lines = [f"{c['clients']} clients, {c['scenes']} scenes, {c['seconds']:.0f} s, mode {c['mode']}"
             f" (≤ {c['edit_rate']} edits/s per client while dragging)",
             f"requests {s['requests']} ({s['throughput_rps']:.1f}/s), edits {s['edits_ok']} "
             f"({s['edits_per_s']:.1f}/s); errors {s['errors']}, timeouts {s['timeouts']}, "
             f"busy (503) {s['busy_503']}; GET p99 {s['get_p99_ms']:.1f} ms",
             f"{'endpoint':<12}{'count':>7}{'p50 ms':>9}{'p95 ms':>9}{'p99 ms':>9}{'max ms':>9}"
             f"{'err':>5}{'t/o':>5}{'503':>6}"]
    for name, e in s["endpoints"].items():
        lines.append(f"{name:<12}{e['count']:>7}{e['p50_ms']:>9.1f}{e['p95_ms']:>9.1f}"
                     f"{e['p99_ms']:>9.1f}{e['max_ms']:>9.1f}{e['errors']:>5}{e['timeouts']:>5}"
                     f"{e['busy_503']:>6}")
    for name, e in s["endpoints"].items():
        if e["errors"]:
            lines.append(f"{name} statuses: {e['statuses']} (-1 timeout, -2 connection error)")
    ev = s["events"]
    lines.append(f"events: {ev['events']} received, {ev['errors']} stream errors, "
                 f"{ev['out_of_order']} out of order")
    if "rss_start_mb" in s:
        lines.append(f"server RSS: start {s['rss_start_mb']:.0f} MB, after warm-up "
                     f"{s['rss_baseline_mb']:.0f} MB, end {s['rss_end_mb']:.0f} MB, max "
                     f"{s['rss_max_mb']:.0f} MB (growth {s['rss_growth_mb']:+.1f} MB); "
                     f"threads ≤ {s['threads_max']}")
    return "\n".join(lines)


def svg_plot(title, series, y_label, width=720, height=220):
    """series: [(name, colour, [(x, y)])] as polylines on shared axes from 0."""
    points = [p for _, _, pts in series for p in pts]
    if not points:
        return ""
    x_max = max(p[0] for p in points) or 1
    y_max = max(p[1] for p in points) * 1.1 or 1
    left, bottom, top, right = 60, 30, 24, 10
    w, h = width - left - right, height - top - bottom

    def xy(p):
        return f"{left + w * p[0] / x_max:.1f},{top + h * (1 - p[1] / y_max):.1f}"

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">',
             f'<text x="{left}" y="16" font-size="13">{htmllib.escape(title)}</text>',
             f'<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="none" stroke="#999"/>']
    for k in range(5):
        y = y_max * k / 4
        parts.append(f'<text x="{left - 4}" y="{top + h * (1 - k / 4) + 4:.1f}" font-size="10" '
                     f'text-anchor="end">{y:.0f}</text>')
    parts.append(f'<text x="{left + w}" y="{height - 8}" font-size="10" text-anchor="end">'
                 f'{x_max:.0f} s</text>')
    parts.append(f'<text x="4" y="{top + h / 2}" font-size="10">{htmllib.escape(y_label)}</text>')
    for i, (name, colour, pts) in enumerate(series):
        parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="'
                     + " ".join(xy(p) for p in pts) + '"/>')
        parts.append(f'<text x="{left + 8 + 140 * i}" y="{top + 14}" font-size="11" '
                     f'fill="{colour}">{htmllib.escape(name)}</text>')
    parts.append("</svg>")
    return "\n".join(parts)


def per_second_p99(samples, endpoint_filter, bucket=10.0):
    buckets = {}
    for endpoint, start, seconds, status in samples:
        if endpoint_filter(endpoint) and 200 <= status < 300:
            buckets.setdefault(int(start // bucket), []).append(seconds)
    return [((k + 0.5) * bucket, 1e3 * percentile(sorted(v), 0.99))
            for k, v in sorted(buckets.items())]


def html(summary, samples, rss):
    rss_plot = svg_plot("Server resident memory (VmRSS)",
                        [("RSS MB", "#c33", [(t, r) for t, r, _ in rss])], "MB")
    latency_plot = svg_plot("p99 latency per 10 s",
                            [("edit", "#36c", per_second_p99(samples, lambda e: e == "edit")),
                             ("GETs", "#393", per_second_p99(samples, lambda e: e != "edit"))],
                            "ms")
    return ("<!doctype html><meta charset='utf-8'><title>penumbra load</title>"
            "<body style='font-family:sans-serif'><h1>penumbra load</h1><pre>"
            + htmllib.escape(text(summary)) + "</pre>" + rss_plot + "<br>" + latency_plot
            + "</body>")
