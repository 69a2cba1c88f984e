//! Writers for the files a slosh run produces (listed in `docs/formats.md`):
//!
//! - [`series`]: `series.csv` time series (+ `series_units.csv`) and other CSV tables;
//! - [`summary`]: pretty RON files such as `summary.ron`;
//! - [`checkpoint`]: versioned, checksummed binary checkpoints, written atomically;
//! - [`vtk`]: VTK XML PolyData `.vtp` particle frames and the ParaView `.pvd` index;
//! - [`plot`]: PNG + SVG figures (line plots, SPH-vs-theory scatter, heatmaps) drawn with a
//!   bundled font, so no system fonts are needed.
//!
//! The crate takes plain slices and knows nothing of the solver's types. Every error is an
//! [`IoError`] naming the file concerned; every writer creates missing parent folders.

#![warn(missing_docs)]

mod base64;
pub mod checkpoint;
pub mod error;
pub mod plot;
pub mod series;
pub mod summary;
pub mod vtk;

pub use checkpoint::{read_checkpoint, write_checkpoint};
pub use error::{create_fresh, open_no_follow, write_atomic, IoError, Result};
pub use plot::{
    heatmap, line_plot, scatter_with_identity, Field2d, PlotSpec, Series, SeriesStyle, PALETTE,
};
pub use series::{
    format_f64, read_table, units_path_for, write_grid_csv, SeriesWriter, Table, TableWriter,
};
pub use summary::{overwrite_ron_in_place, read_ron, write_ron};
pub use vtk::{write_vtp, ArrayData, FrameSeries, PointArray, PvdIndex};
