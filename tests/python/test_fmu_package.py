"""Packaging of both FMUs: reproducible archives (the same bytes from the same build), the crate
sources in sources/ form a Cargo workspace that builds the binary, author/copyright/license."""
import pathlib
import json
import subprocess
import zipfile

import pytest

from repo import BIN, FMU_DIR, ROOT

PACKAGERS = {
    "CncMotion": lambda out: [str(BIN / "cnc-motion"), "package", "--output", str(out)],
    "MachineStructure": lambda out: [str(BIN / "package-machine-structure"), str(out)],
}


@pytest.mark.parametrize("name", PACKAGERS)
def test_repackaging_gives_the_same_bytes(fmus: tuple[pathlib.Path, pathlib.Path], name: str,
                                          tmp_path: pathlib.Path) -> None:
    """`make fmu` wrote the FMU earlier (other timestamps): packaging again is byte-identical."""
    out = tmp_path / f"{name}.fmu"
    subprocess.run(PACKAGERS[name](out), check=True, capture_output=True)
    assert out.read_bytes() == (FMU_DIR / f"{name}.fmu").read_bytes()
    # The FMI 3.0 archive written beside it too.
    assert (tmp_path / f"{name}-fmi3.fmu").read_bytes() == (FMU_DIR / f"{name}-fmi3.fmu").read_bytes()


@pytest.mark.parametrize("name,crates", [("CncMotion", {"cnc-motion", "fmi2", "fmi3"}),
                                         ("MachineStructure", {"machine-structure", "fmi2", "fmi3"})])
def test_sources_are_a_cargo_workspace(fmus: tuple[pathlib.Path, pathlib.Path], name: str, crates: set[str],
                                       tmp_path: pathlib.Path) -> None:
    with zipfile.ZipFile(FMU_DIR / f"{name}.fmu") as z:
        names = z.namelist()
        assert [n for n in names if n.startswith("sources/")] == sorted(n for n in names if n.startswith("sources/"))
        z.extractall(tmp_path, [n for n in names if n.startswith("sources/")])
    src = tmp_path / "sources"
    assert (src / "README.md").exists() and (src / "src" / "lib.rs").exists() and (src / "Cargo.lock").exists()
    # Rust, not C: no SourceFiles declared (an importer must not try to compile them); the README
    # says how to build each platform, with the declared minimum Rust version.
    from fmpy import read_model_description
    md = read_model_description(str(ROOT / "target" / "fmu" / f"{name}.fmu"))
    assert md.buildConfigurations == []
    readme = (src / "README.md").read_text()
    line = next(l for l in (ROOT / "Cargo.toml").read_text().splitlines() if l.startswith("rust-version"))
    rust_version = line.split('"')[1]
    assert f"Rust {rust_version} or newer" in readme, readme
    assert "--target x86_64-pc-windows-gnu" in readme and "binaries/win64/" in readme
    res = subprocess.run(["cargo", "metadata", "--offline", "--no-deps", "--format-version", "1"],
                         cwd=src, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    meta = json.loads(res.stdout)
    assert {p["name"] for p in meta["packages"]} == crates
    lib = next(t for p in meta["packages"] if p["name"] not in ("fmi2", "fmi3") for t in p["targets"]
               if "cdylib" in t["kind"])
    assert lib["name"] in ("cnc_motion", "machine_structure")


@pytest.mark.parametrize("name", PACKAGERS)
def test_author_copyright_license(fmus: tuple[pathlib.Path, pathlib.Path], name: str) -> None:
    from fmpy import read_model_description
    md = read_model_description(str(FMU_DIR / f"{name}.fmu"))
    assert md.author and md.license == "MIT" and md.copyright.startswith("Copyright")
