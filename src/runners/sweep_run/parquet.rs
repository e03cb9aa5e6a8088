//! A sweep's results table written as Parquet (docs/sweep.md §4) with the Apache Arrow project's
//! `parquet` crate: one row group, every column optional, Snappy pages. The file depends on the
//! rows only (no time stamp), so the same runs give the same bytes. Runtime layer (files).

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use parquet::basic::{Compression, LogicalType, Repetition, Type as Physical};
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::errors::ParquetError;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;

use crate::sweep::metrics::Scalar;
use crate::sweep::results::{Column, ColumnKind};

/// Writes `columns` (all of the same length) to `path`.
pub fn write(path: &Path, columns: &[Column]) -> Result<(), String> {
    let fail = |e: ParquetError| format!("cannot write {}: {e}", path.display());
    let file = File::create(path).map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let fields = columns
        .iter()
        .map(|c| field(c).map(Arc::new))
        .collect::<Result<Vec<_>, _>>()
        .map_err(fail)?;
    let schema = Type::group_type_builder("rotorpilot_sweep")
        .with_fields(fields)
        .build()
        .map_err(fail)?;
    let props = WriterProperties::builder().set_compression(Compression::SNAPPY).build();
    let mut writer = SerializedFileWriter::new(file, Arc::new(schema), Arc::new(props)).map_err(fail)?;
    let mut group = writer.next_row_group().map_err(fail)?;
    for column in columns {
        let Some(mut out) = group.next_column().map_err(fail)? else {
            return Err(format!("{}: the schema lost column {}", path.display(), column.name));
        };
        let levels: Vec<i16> = column.cells.iter().map(|c| i16::from(c.is_some())).collect();
        match column.kind {
            ColumnKind::Int => {
                let values = present(column, |s| if let Scalar::Int(i) = s { Some(*i) } else { None });
                out.typed::<Int64Type>().write_batch(&values, Some(&levels), None)
            }
            ColumnKind::Float => {
                let values = present(column, |s| if let Scalar::Float(x) = s { Some(*x) } else { None });
                out.typed::<DoubleType>().write_batch(&values, Some(&levels), None)
            }
            ColumnKind::Bool => {
                let values = present(column, |s| if let Scalar::Bool(b) = s { Some(*b) } else { None });
                out.typed::<BoolType>().write_batch(&values, Some(&levels), None)
            }
            ColumnKind::Text => {
                let values = present(column, |s| {
                    if let Scalar::Text(t) = s {
                        Some(ByteArray::from(t.as_str()))
                    } else {
                        None
                    }
                });
                out.typed::<ByteArrayType>().write_batch(&values, Some(&levels), None)
            }
        }
        .map_err(fail)?;
        out.close().map_err(fail)?;
    }
    group.close().map_err(fail)?;
    writer.close().map_err(fail)?;
    Ok(())
}

/// The present cells of `column` as `pick` reads them (the column's kind: every cell matches).
fn present<T>(column: &Column, pick: impl Fn(&Scalar) -> Option<T>) -> Vec<T> {
    column.cells.iter().flatten().filter_map(pick).collect()
}

/// The Parquet field of a column.
fn field(c: &Column) -> Result<Type, ParquetError> {
    let (physical, logical) = match c.kind {
        ColumnKind::Int => (Physical::INT64, None),
        ColumnKind::Float => (Physical::DOUBLE, None),
        ColumnKind::Bool => (Physical::BOOLEAN, None),
        ColumnKind::Text => (Physical::BYTE_ARRAY, Some(LogicalType::String)),
    };
    Type::primitive_type_builder(&c.name, physical)
        .with_repetition(Repetition::OPTIONAL)
        .with_logical_type(logical)
        .build()
}
