"""Compare two builds' planned values written by the feed bench's digest mode.

    FEED_DIGEST=1 FEED_VALUES=/tmp/a.txt <bench binary of build A>   (from the repository root)
    FEED_DIGEST=1 FEED_VALUES=/tmp/b.txt <bench binary of build B>
    python3 benches/feed_values_diff.py /tmp/a.txt /tmp/b.txt

Plans (one per program and corner policy) whose structure is the same (the same segments,
caps and active limits, values differing only in size) are compared value by value: the largest
absolute difference, and the largest relative one over values above 1e-9 in size. Plans whose
structure differs (a blend decided otherwise, a cap named otherwise) are counted, with their
cycle times' relative difference.
"""
import sys


def plans(path):
    """The values of each plan: lists of (kind, text)."""
    out, cur = [], None
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line == "plan":
                cur = []
                out.append(cur)
            elif cur is not None:
                kind, _, text = line.partition(" ")
                cur.append((kind, text))
    return out


a, b = plans(sys.argv[1]), plans(sys.argv[2])
if len(a) != len(b):
    sys.exit(f"different numbers of plans: {len(a)} and {len(b)}")
same = differ = identical = 0
worst_abs = worst_rel = worst_cycle = worst_cycle_struct = 0.0
where = ""
for i, (pa, pb) in enumerate(zip(a, b)):
    if pa == pb:
        identical += 1
    cycle = None
    if pa and pb and pa[0][0] == "f" and pb[0][0] == "f":
        x, y = float(pa[0][1]), float(pb[0][1])
        cycle = abs(x - y) / max(abs(x), abs(y), 1e-300)
    structure = len(pa) == len(pb) and all(
        ka == kb and (ka == "f" or ta == tb) for (ka, ta), (kb, tb) in zip(pa, pb)
    )
    if not structure:
        differ += 1
        if cycle is not None:
            worst_cycle_struct = max(worst_cycle_struct, cycle)
        continue
    same += 1
    if cycle is not None:
        worst_cycle = max(worst_cycle, cycle)
    for (ka, ta), (_, tb) in zip(pa, pb):
        if ka != "f":
            continue
        x, y = float(ta), float(tb)
        if x == y:
            continue
        d = abs(x - y)
        worst_abs = max(worst_abs, d)
        m = max(abs(x), abs(y))
        if m > 1e-9 and d / m > worst_rel:
            worst_rel = d / m
            where = f"plan {i}: {x!r} vs {y!r}"
print(f"plans {len(a)}: {identical} identical, {same} with the same structure, {differ} with another")
print(f"same structure: max abs diff {worst_abs:.3e}, max rel diff {worst_rel:.3e} ({where}), "
      f"max cycle-time rel diff {worst_cycle:.3e}")
print(f"other structure: max cycle-time rel diff {worst_cycle_struct:.3e}")
