//! The one low-level NetCDF reader of the project: a file opened with the
//! pure-Rust `netcdf-reader` crate, which reads the classic formats (CDF-1,
//! 64-bit offset CDF-2, 64-bit data CDF-5) and NetCDF-4 (HDF5, through its
//! own pure-Rust `hdf5-reader`: contiguous and chunked storage, deflate
//! (zlib), shuffle and Fletcher-32 filters), so that `cargo` alone builds
//! the project. This module gives the rest of [`crate::model::netcdf`] (and the
//! reader of `trajectory.nc`, [`crate::run::netcdf_out`]) the few
//! questions the CF logic asks (variables, dimensions, attributes, values
//! as `f64`) the same way for every format; the CF meaning of those values
//! (packing, fill values, units, time axes) is decided once, in
//! [`NcInput::values`] and in `grid.rs`.
//!
//! Only the root group is read: a variable in a NetCDF-4 sub-group is
//! reported as missing (with the root group's variables listed). Variables
//! of string, character or user-defined (compound, enum, opaque,
//! variable-length) types are refused when read as numbers.

use netcdf_reader::{NcAttrValue, NcFile, NcType, NcVariable};
use std::path::Path;

/// An open NetCDF file and its name for error messages.
pub(crate) struct NcInput {
    /// The path as the messages print it.
    file: String,
    /// The open file.
    nc: NcFile,
}

/// NetCDF's default fill value of a numeric type (NetCDF User Guide,
/// "Fill values"), the value a reader must treat as missing when the
/// variable has no `_FillValue`; `None` for types without one here.
fn default_fill(t: &NcType) -> Option<f64> {
    Some(match t {
        NcType::Byte => -127.0,
        NcType::Short => -32767.0,
        NcType::Int => -2_147_483_647.0,
        NcType::Float => f64::from(9.969_21e36_f32),
        NcType::Double => 9.969_209_968_386_869e36,
        NcType::UByte => 255.0,
        NcType::UShort => 65535.0,
        NcType::UInt => 4_294_967_295.0,
        // The 64-bit fills as f64 (the nearest doubles, as the values are
        // compared after the same conversion).
        NcType::Int64 => -9_223_372_036_854_775_806_i64 as f64,
        NcType::UInt64 => 18_446_744_073_709_551_614_u64 as f64,
        _ => return None,
    })
}

impl NcInput {
    /// Opens `path`, classic or NetCDF-4 (told apart by the file's magic
    /// bytes). The error names the file and, for an HDF5 file that the
    /// reader cannot decode, says it is NetCDF-4.
    pub(crate) fn open(path: &Path) -> Result<Self, String> {
        let file = path.display().to_string();
        // The root group's metadata is read here, so that a damaged file is
        // refused at once rather than seen as a file without variables.
        let opened = NcFile::open(path).and_then(|nc| nc.variables().map(|_| ()).map(|()| nc));
        match opened {
            Ok(nc) => Ok(NcInput { file, nc }),
            Err(e) => {
                let mut head = [0u8; 8];
                let hdf5 = std::fs::File::open(path)
                    .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
                    .is_ok()
                    && head.starts_with(b"\x89HDF");
                Err(if hdf5 {
                    format!("{file} is NetCDF-4 (HDF5) but cannot be read: {e}")
                } else {
                    format!("{file}: not a NetCDF file ({e})")
                })
            }
        }
    }

    /// The file's name as the messages print it.
    pub(crate) fn file(&self) -> &str {
        &self.file
    }

    /// The root group's variables (read by [`NcInput::open`], so never an
    /// error here).
    fn variables(&self) -> &[NcVariable] {
        self.nc.variables().unwrap_or_default()
    }

    /// The variable `name` of the root group.
    fn variable(&self, name: &str) -> Option<&NcVariable> {
        self.variables().iter().find(|v| v.name() == name)
    }

    /// Whether the root group has a variable `name`.
    pub(crate) fn has_var(&self, name: &str) -> bool {
        self.variable(name).is_some()
    }

    /// The names of the root group's variables.
    pub(crate) fn var_names(&self) -> Vec<String> {
        self.variables()
            .iter()
            .map(|v| v.name().to_string())
            .collect()
    }

    /// The dimensions of variable `name` (names and sizes), in the file's
    /// order; empty if there is no such variable.
    pub(crate) fn dims(&self, name: &str) -> Vec<(String, usize)> {
        self.variable(name)
            .map(|v| {
                v.dimensions()
                    .iter()
                    .map(|d| {
                        (
                            d.name.clone(),
                            usize::try_from(d.size).unwrap_or(usize::MAX),
                        )
                    })
                    .collect()
            })
            .unwrap_or_default()
    }

    /// A text attribute of a variable (`NC_CHAR`, or a single `NC_STRING`).
    pub(crate) fn attr_string(&self, var: &str, name: &str) -> Option<String> {
        self.variable(var)?.attribute(name)?.value.as_string()
    }

    /// The first value of a numeric attribute of a variable, as `f64`.
    pub(crate) fn attr_f64(&self, var: &str, name: &str) -> Option<f64> {
        match &self.variable(var)?.attribute(name)?.value {
            NcAttrValue::Chars(_) | NcAttrValue::Strings(_) => None,
            v => v.as_f64(),
        }
    }

    /// A numeric variable's stored values as `f64`, in C (row-major) order,
    /// not unpacked.
    pub(crate) fn raw(&self, name: &str) -> Result<Vec<f64>, String> {
        let file = &self.file;
        let v = self
            .variable(name)
            .ok_or_else(|| format!("{file}: no variable `{name}`"))?;
        if default_fill(v.dtype()).is_none() {
            return Err(format!(
                "{file}: variable `{name}` is of type {:?}, not a number",
                v.dtype()
            ));
        }
        self.nc
            .read_variable_as_f64(name)
            .map(|a| a.iter().copied().collect())
            .map_err(|e| format!("{file}: cannot read variable `{name}`: {e}"))
    }

    /// A numeric variable's values in C order, unpacked by CF's
    /// `scale_factor` and `add_offset` (`x · scale + offset`); `None` marks
    /// a missing value: the stored value equals `_FillValue`,
    /// `missing_value`, or the type's default fill, or is not finite.
    pub(crate) fn values(&self, name: &str) -> Result<Vec<Option<f64>>, String> {
        let raw = self.raw(name)?;
        let attr = |a: &str| self.attr_f64(name, a);
        let scale = attr("scale_factor").unwrap_or(1.0);
        let offset = attr("add_offset").unwrap_or(0.0);
        let default = self.variable(name).and_then(|v| default_fill(v.dtype()));
        let fills: Vec<f64> = [attr("_FillValue"), attr("missing_value"), default]
            .into_iter()
            .flatten()
            .collect();
        Ok(raw
            .into_iter()
            .map(|x| {
                let missing = !x.is_finite() || fills.contains(&x);
                (!missing).then_some(x * scale + offset)
            })
            .collect())
    }
}
