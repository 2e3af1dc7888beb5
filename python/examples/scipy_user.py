"""A scipy user's calls of ``hrla.minimize``, typed: ``mypy --strict``
checks this file against the package's annotations and stubs
(``scripts/test-python.sh`` runs it)."""

from typing import Tuple

import numpy as np
import numpy.typing as npt

import hrla

F64 = npt.NDArray[np.float64]


def himmelblau(x: F64) -> float:
    return float((x[0] ** 2 + x[1] - 11) ** 2 + (x[0] + x[1] ** 2 - 7) ** 2)


def with_gradient(x: F64) -> Tuple[float, F64]:
    p, q = x[0] ** 2 + x[1] - 11, x[0] + x[1] ** 2 - 7
    return float(p * p + q * q), np.array([4 * x[0] * p + 2 * q, 2 * p + 4 * x[1] * q])


def columns(x: F64) -> F64:
    p, q = x[0] ** 2 + x[1] - 11, x[0] + x[1] ** 2 - 7
    return np.asarray(p * p + q * q, dtype=np.float64)


def stop_early(intermediate_result: hrla.OptimizeResult) -> bool:
    return bool(intermediate_result.fun < 1e-8)


def main() -> None:
    res: hrla.OptimizeResult = hrla.minimize(himmelblau, [(-5, 5), (-5, 5)], rng=1, maxfun=20_000)
    x: F64 = res.x
    print(x, res.fun, res.nfev, res.success, res.message)
    res = hrla.minimize(with_gradient, [(-5, 5)] * 2, jac=True, method="hrla", rng=np.random.default_rng(2),
                        callback=stop_early, maxtime=10.0)
    res = hrla.minimize(columns, [(-5, 5)] * 2, vectorized=True, target=1e-10, disp=False)
    res = hrla.minimize(hrla.Rastrigin(), [(-5.12, 5.12)] * 3, stall=(20, 0.0), maxiter=500)
    opt = hrla.Optimizer(hrla.Rastrigin(), hrla.Hrla.paper(0.01), 4.0, hrla.Interval(-5.12, 5.12), dim=3, seed=1,
                         stop=hrla.Stop().steps(100))
    report: hrla.Report = opt.run(lambda iteration, evaluations, value: value < 1e-3)
    print(report.termination, hrla.__version__)


if __name__ == "__main__":
    main()
