"""The paper's Table 1 from Python: Newmark and Simpson on the pendulum, errors at 50, 100 and 200
steps per period and the observed orders (Dubois & Rojas-Quintero 2023, Table 1).

    python3 examples/python/table1.py
"""
import math

import varsym

table = varsym.table1()
print(f"{'scheme':8} {'quantity':9} {'N':>4} {'error':>10} {'order':>6}")
for scheme in ("newmark", "simpson"):
    for quantity in ("momentum", "state", "energy"):
        rows = sorted((r for r in table if r["scheme"] == scheme and r["quantity"] == quantity),
                      key=lambda r: r["steps"])
        for prev, row in zip([None] + rows[:-1], rows):
            order = "" if prev is None else f"{math.log2(prev['error'] / row['error']):6.2f}"
            print(f"{scheme:8} {quantity:9} {row['steps']:4d} {row['error']:10.3g} {order:>6}")
simpson = [r["error"] for r in table if r["scheme"] == "simpson" and r["quantity"] == "state"]
assert max(simpson) < 2e-6, simpson  # the paper prints 1.05e-6 at N = 50
print("OK")
