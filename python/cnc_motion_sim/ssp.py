"""Build examples/cosim.ssp: CncMotion.fmu and MachineStructure.fmu with the two-way force coupling.

    python -m cnc_motion_sim.ssp [--cnc CncMotion.fmu] [--structure MachineStructure.fmu] [--out cosim.ssp]

(the FMUs default to the ones shipped in this package; `make ssp` writes examples/cosim.ssp).

Connections (SSP 1.0, read by fmpy.ssp and libcosim):
    cnc.{x,y,z}.driveForce      → structure.{x,y,z}.driveForce
    structure.{x,y,z}.loadForce → cnc.{x,y,z}.loadForce
Besides the connected ports, the components list the outputs that fmpy.ssp should record
(fmpy.ssp records every connector). Inputs that are not connected are not listed, because fmpy.ssp
writes every listed input at each step. Start values stay those of the FMUs (no parameter bindings):
fmpy.ssp does not apply bindings and both masters must run the same system.
"""
from __future__ import annotations

import argparse
import atexit
import pathlib
import shutil
import tempfile
import zipfile
from collections.abc import Mapping
from typing import Any
from xml.sax.saxutils import quoteattr

from fmpy import read_model_description

from .fmu import AXES
from .paths import CNC_FMU, STRUCTURE_FMU, PathLike, fmu_file

Connection = tuple[str, str, str, str]

CNC_RECORDED = [f"{a}.command.{q}" for a in AXES for q in ("position", "velocity", "acceleration", "jerk")] + [
    "path.feed", "path.distance", "status.line", "status.finished"] + [
    f"{a}.{q}" for a in AXES for q in ("position", "followingError")]
STRUCTURE_RECORDED = [f"{a}.{q}" for a in AXES for q in ("deflection", "acceleration")]

SSD_NS = ('xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
          'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" '
          'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"')


def connections() -> list[Connection]:
    """(from component, from variable, to component, to variable) for the coupling."""
    out = []
    for a in AXES:
        out.append(("cnc", f"{a}.driveForce", "structure", f"{a}.driveForce"))
        out.append(("structure", f"{a}.loadForce", "cnc", f"{a}.loadForce"))
    return out


def _connector(var: Any) -> str:
    kind = var.causality
    ty = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean", "Enumeration": "Integer"}[var.type]
    return f'        <ssd:Connector name={quoteattr(var.name)} kind="{kind}"><ssc:{ty}/></ssd:Connector>'


def bindings_xml(params: Mapping[str, Any] | None) -> str:
    """Inline parameter values of a component (Python ints as Integer, the rest as Real; e.g. the
    Integer `machine.profileIndex`, which importers without Enumerations can set). libcosim applies
    them; fmpy.ssp does not (pass the same values to simulate_ssp as parameter_set, see
    cosim.cosim_fmpy_ssp)."""
    if not params:
        return ""

    def value(v: Any) -> str:
        return f'<ssv:Integer value="{v}"/>' if isinstance(v, int) else f'<ssv:Real value="{float(v)!r}"/>'
    rows = "\n".join(f'              <ssv:Parameter name={quoteattr(k)}>{value(v)}</ssv:Parameter>'
                     for k, v in params.items())
    return f"""      <ssd:ParameterBindings>
        <ssd:ParameterBinding>
          <ssd:ParameterValues>
            <ssv:ParameterSet version="1.0" name="values">
              <ssv:Parameters>
{rows}
              </ssv:Parameters>
            </ssv:ParameterSet>
          </ssd:ParameterValues>
        </ssd:ParameterBinding>
      </ssd:ParameterBindings>
"""


def component_xml(name: str, fmu_path: pathlib.Path, wanted: list[str],
                  params: Mapping[str, Any] | None = None) -> str:
    md = read_model_description(str(fmu_path))
    by_name = {v.name: v for v in md.modelVariables}
    missing = [w for w in wanted if w not in by_name]
    if missing:
        raise SystemExit(f"{fmu_path.name}: no variables {missing}")
    lines = [f'    <ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" '
             f'source="resources/{fmu_path.name}">', "      <ssd:Connectors>"]
    lines += [_connector(by_name[w]) for w in wanted]
    lines += ["      </ssd:Connectors>"]
    if params:
        lines.append(bindings_xml(params).rstrip("\n"))
    lines += ["    </ssd:Component>"]
    return "\n".join(lines)


def ssd_text(cnc_fmu: pathlib.Path, structure_fmu: pathlib.Path, stop_time: float,
             structure_params: Mapping[str, Any] | None = None, cnc_params: Mapping[str, Any] | None = None) -> str:
    conns = connections()
    ports: dict[str, list[str]] = {"cnc": [], "structure": []}
    for fc, fv, tc, tv in conns:
        ports[fc].append(fv)
        ports[tc].append(tv)
    cnc_ports = ports["cnc"] + [n for n in CNC_RECORDED if n not in ports["cnc"]]
    st_ports = ports["structure"] + [n for n in STRUCTURE_RECORDED if n not in ports["structure"]]
    conn_xml = "\n".join(
        f'    <ssd:Connection startElement="{fc}" startConnector="{fv}" endElement="{tc}" endConnector="{tv}"/>'
        for fc, fv, tc, tv in conns)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {SSD_NS} version="1.0" name="CncOnFrame">
  <ssd:System name="CncOnFrame" description="CNC motion controller driving a modal machine frame">
  <ssd:Elements>
{component_xml("cnc", cnc_fmu, cnc_ports, cnc_params)}
{component_xml("structure", structure_fmu, st_ports, structure_params)}
  </ssd:Elements>
  <ssd:Connections>
{conn_xml}
  </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0.0" stopTime="{stop_time}"/>
</ssd:SystemStructureDescription>
"""


def make_ssp(out: PathLike, cnc_fmu: PathLike | None = None, structure_fmu: PathLike | None = None,
             stop_time: float = 8.0, structure_params: Mapping[str, Any] | None = None,
             cnc_params: Mapping[str, Any] | None = None) -> pathlib.Path:
    """Write the SSP to `out` (the FMUs: the given ones, else those shipped in this package).
    `structure_params`, `cnc_params`: {variable: value} bound in the SSP (e.g. {"x.couplingMass": 1.0},
    {"machine.profileIndex": 5})."""
    cnc_path, structure_path = fmu_file(cnc_fmu, CNC_FMU), fmu_file(structure_fmu, STRUCTURE_FMU)
    out = pathlib.Path(out)
    text = ssd_text(cnc_path, structure_path, stop_time, structure_params, cnc_params)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", text)
        z.write(cnc_path, f"resources/{cnc_path.name}")
        z.write(structure_path, f"resources/{structure_path.name}")
    tmp.replace(out)
    return out


_default: list[pathlib.Path] = []


def default_ssp() -> pathlib.Path:
    """The SSP of the FMUs shipped in this package, written once per process to a temporary
    folder (removed at exit)."""
    if not _default:
        folder = pathlib.Path(tempfile.mkdtemp(prefix="cnc_motion_ssp_"))
        atexit.register(shutil.rmtree, folder, ignore_errors=True)
        _default.append(make_ssp(folder / "cosim.ssp"))
    return _default[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--cnc", help="CncMotion.fmu (default: the one shipped in this package)")
    ap.add_argument("--structure", help="MachineStructure.fmu (default: the one shipped in this package)")
    ap.add_argument("--out", default="cosim.ssp")
    ap.add_argument("--stop-time", type=float, default=8.0)
    a = ap.parse_args()
    print(make_ssp(a.out, a.cnc, a.structure, a.stop_time))


if __name__ == "__main__":
    main()
