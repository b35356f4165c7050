//! Reports: plots, tables and the report page.

pub mod plot;
