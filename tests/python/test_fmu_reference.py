"""The reference result each FMU ships, as the Modelica Reference-FMUs do (FMI layered standard for
reference results): `extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml` names a CSV of the
outputs of the default experiment, written when the FMU was packaged. A fresh simulation of the
default experiment with fmpy (its stop time and step size from the DefaultExperiment) gives the
same numbers: the interpolator's outputs (command, path, status) bit for bit, the continuous ones
(drives, structure) within 1e-9 of each column's range plus 1e-12 (SI) — fmpy forms its communication points in
its own floating-point way, and the sub-stepped drives see step lengths that differ in the last
bits (seen: 1e-13 of the range; integer time in the engine removes that)."""
import csv
import pathlib
import io
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from repo import ROOT

LS = "extra/org.fmi-standard.fmi-ls-ref/"


@pytest.mark.parametrize("name", ["CncMotion", "MachineStructure"])
def test_reference_result_equals_a_fresh_simulation(fmus: tuple[pathlib.Path, pathlib.Path], name: str) -> None:
    path = ROOT / "target" / "fmu" / f"{name}.fmu"
    with zipfile.ZipFile(path) as z:
        manifest = ET.fromstring(z.read(LS + "fmi-ls-manifest.xml"))
        assert manifest.get("{http://fmi-standard.org/fmi-ls-manifest}fmi-ls-name") == "org.fmi-standard.fmi-ls-ref"
        related = manifest.find("Related")
        assert related is not None and related.get("role") == "result" and related.get("type") == "text/csv"
        rows = list(csv.reader(io.StringIO(z.read(LS + related.get("source", "")).decode())))
    header, ref = rows[0], np.array(rows[1:], dtype=float)
    md = read_model_description(str(path))
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    assert header == ["time"] + outputs
    exp = md.defaultExperiment
    res = simulate_fmu(str(path), stop_time=float(exp.stopTime), output_interval=float(exp.stepSize),
                       output=outputs)
    every = int(round((ref[1, 0] - ref[0, 0]) / float(exp.stepSize)))
    fresh = res[::every]
    assert len(fresh) == len(ref), (len(fresh), len(ref))
    assert np.allclose(fresh["time"], ref[:, 0], rtol=0, atol=1e-9)
    continuous = {v.name for v in md.modelVariables if v.causality == "output" and v.variability == "continuous"}
    for k, n in enumerate(outputs, start=1):
        got, want = fresh[n].astype(float), ref[:, k]
        if n in continuous:
            assert np.max(np.abs(got - want)) <= 1e-9 * np.max(np.abs(want)) + 1e-12, n
        else:
            assert np.array_equal(got, want), f"{n}: largest difference {np.max(np.abs(got - want))}"
    if name == "CncMotion":
        assert ref[-1, header.index("status.finished")] == 1.0, "the default program ends within the experiment"
