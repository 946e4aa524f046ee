"""Ad-hoc timing: the core's Jacobian against its FK and the references' per-call Jacobians.

``python benchmarks/jacobian_timing.py`` (UR5, 100 000 configurations, best of 3
for the batched calls, 5 000 configurations in a Python loop for the references).
Until ``fkcheck bench --jacobian`` exists this is not like for like: the core is
batched, the references are called once per configuration.
"""

import time
from collections.abc import Callable

import numpy as np

import fkcheck
from fkcheck.backends.pinocchio_dh import PinocchioChain
from fkcheck.backends.rtb_dh import dh_robot


def best_s(run: Callable[[], object], repeat: int = 3) -> float:
    out = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        out = min(out, time.perf_counter() - start)
    return out


def ns(seconds: float) -> str:
    return f"{seconds * 1e9:.0f} ns"


def main() -> None:
    model = fkcheck.load_model("ur5")
    q = np.random.default_rng(0).uniform(-3, 3, (100_000, 6))
    model.fk(q)  # compile / load the JIT first
    model.jacobian(q[:10])
    n = q.shape[0]
    fk_tcp = best_s(lambda: model.fk(q)) / n
    fk_all = best_s(lambda: model.fk(q, all_frames=True)) / n
    jac = best_s(lambda: model.jacobian(q)) / n
    ets = dh_robot(model).ets()
    few = q[:5000]
    rtb = best_s(lambda: [ets.jacob0(x) for x in few], 1) / len(few)
    chain = PinocchioChain(model, tcp_only=True)
    assert chain.tcp_frame_id is not None
    tcp = chain.tcp_frame_id
    pin = best_s(lambda: chain.jacobians(few, tcp, "world-aligned"), 1) / len(few)
    print(
        f"UR5, N={n}: fk TCP {ns(fk_tcp)}/pose, fk all frames {ns(fk_all)}, "
        f"core Jacobian {ns(jac)}/J ({jac / fk_tcp:.0f}x fk TCP); "
        f"RTB ETS.jacob0 per q {ns(rtb)} ({rtb / jac:.1f}x ours); "
        f"Pinocchio computeFrameJacobian per q {ns(pin)} ({pin / jac:.1f}x ours)"
    )


if __name__ == "__main__":
    main()
