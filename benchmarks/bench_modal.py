"""How long a modal run of the study case takes (build excluded).

Medians of repeats, in-process (assembly + eigensolution + classification) and as a
whole `pygear modal --json` process, against the bare generalized eigensolution of
the same matrices as the baseline measured in the same run.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import scipy.linalg
from timing import median_seconds

from pygear import load_case
from pygear.analysis.modes.modal import modal_analysis
from pygear.assembly import assemble

CASE = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"


def main() -> None:
    case = load_case(CASE)
    model = assemble(case, formulation="improved", dof_set="planar")
    baseline = median_seconds(lambda: scipy.linalg.eigh(model.stiffness, model.mass), 200)
    rows = [("eigh(K, M) alone (baseline)", baseline)]
    for dof_set in ("planar", "spatial"):
        rows.append(
            (
                f"assemble, {dof_set}",
                median_seconds(
                    lambda d=dof_set: assemble(case, formulation="improved", dof_set=d), 50
                ),
            )
        )
        rows.append(
            (
                f"assemble + modal analysis, {dof_set}",
                median_seconds(
                    lambda d=dof_set: modal_analysis(
                        assemble(case, formulation="improved", dof_set=d)
                    ),
                    50,
                ),
            )
        )
    command = [sys.executable, "-m", "pygear.cli", "modal", str(CASE), "--json"]
    rows.append(
        (
            "`pygear modal --json` process",
            median_seconds(lambda: subprocess.run(command, check=True, capture_output=True), 5),
        )
    )
    print(f"{'what':<40} {'median [ms]':>12} {'x baseline':>11}")
    for name, seconds in rows:
        print(f"{name:<40} {seconds * 1e3:>12.2f} {seconds / baseline:>11.1f}")


if __name__ == "__main__":
    main()
