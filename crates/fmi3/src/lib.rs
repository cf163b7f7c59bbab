//! The FMI 3.0 side of the generic layer (Co-Simulation, with Event Mode and Scheduled Execution
//! for models that declare clocks): the same [`fmi2::Model`], table, instance and state machine as
//! FMI 2 (crates/fmi2), seen through a [`View`] that gathers the per-axis variables into arrays,
//! gives them the FMI 3 types and adds the clocks; the fmi3 C functions ([`abi`],
//! [`export_fmi3!`]), modelDescription.xml and terminalsAndIcons.xml ([`xml`]) and the reference
//! result with array cells ([`reference`]). One cdylib exports both versions' functions, so the
//! FMI 3 archive ships the very binaries of the FMI 2 one.

pub mod abi;
#[macro_use]
pub mod export;
pub mod reference;
pub mod view;
pub mod xml;

#[doc(hidden)]
pub use export::__LogMessageFn;
pub use view::{Kind, Var, View};

/// The FMI 2 layer this one builds on (for the macro's users).
pub use fmi2;

use fmi2::Model;

/// Where the FMI 3.0 archive of a model goes beside its FMI 2.0 one: `CncMotion.fmu` →
/// `CncMotion-fmi3.fmu` (the FMI 2 names stay what importers and scripts already use).
pub fn archive_path(fmi2_archive: &std::path::Path) -> std::path::PathBuf {
    let stem = fmi2_archive
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("model");
    fmi2_archive.with_file_name(format!("{stem}-fmi3.fmu"))
}

/// modelDescription.xml (FMI 3.0) of a model, start values read from a default model.
pub fn model_description<M: Model>() -> String {
    xml::model_description(M::info(), &View::of::<M>(), &fmi2::start_values::<M>())
}

/// terminalsAndIcons/terminalsAndIcons.xml of a model, if it declares terminals.
pub fn terminals_and_icons<M: Model>() -> Option<String> {
    xml::terminals_and_icons(M::info())
}
