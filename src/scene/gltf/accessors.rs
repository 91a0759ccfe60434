//! Buffers, buffer views and accessors: the buffers loaded (GLB BIN chunk, data
//! URI or file), every view and accessor checked to lie inside its data (so the
//! crate's readers cannot panic), and accessors read.

use std::path::Path;

use gltf::Document;
use gltf::accessor::{Accessor, DataType, Dimensions, Item};
use gltf::buffer::Data as BufferData;

use super::Loaded;

/// Largest size in bytes of an accessor without a buffer view (its elements
/// are zeros, allocated from the declared count alone).
const MAX_ZERO_FILLED_BYTES: usize = 64 << 20;

pub(super) fn load_buffers(
    document: &Document,
    base_dir: Option<&Path>,
    bin: Option<&[u8]>,
) -> Loaded<Vec<BufferData>> {
    let mut blob = bin.map(<[u8]>::to_vec);
    document
        .buffers()
        .map(|buffer| load_buffer(&buffer, base_dir, &mut blob))
        .collect()
}

fn load_buffer(
    buffer: &gltf::Buffer,
    base_dir: Option<&Path>,
    blob: &mut Option<Vec<u8>>,
) -> Loaded<BufferData> {
    let label = match buffer.source() {
        gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => {
            format!("buffer {} (\"{uri}\")", buffer.index())
        }
        _ => format!("buffer {}", buffer.index()),
    };
    if let gltf::buffer::Source::Bin = buffer.source() {
        let Some(bin) = blob.as_ref() else {
            return Err(format!(
                "{label} has no uri and there is no (unclaimed) GLB BIN chunk"
            ));
        };
        if bin.len() < buffer.length() {
            return Err(format!(
                "{label}: byteLength is {} but the GLB BIN chunk holds only {} bytes",
                buffer.length(),
                bin.len()
            ));
        }
    }
    let data = BufferData::from_source_and_blob(buffer.source(), base_dir, blob)
        .map_err(|e| format!("{label}: cannot load: {e}"))?;
    if data.len() < buffer.length() {
        return Err(format!(
            "{label}: byteLength is {} but the data holds only {} bytes",
            buffer.length(),
            data.len()
        ));
    }
    Ok(data)
}

pub(super) fn check_views(document: &Document, buffers: &[BufferData]) -> Loaded<()> {
    for view in document.views() {
        let buffer = view.buffer();
        let available = buffer.length().min(buffers[buffer.index()].len());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|end| end > available) {
            return Err(format!(
                "buffer view {}: {} bytes from byte {} do not fit buffer {} ({available} bytes)",
                view.index(),
                view.length(),
                view.offset(),
                buffer.index()
            ));
        }
    }
    Ok(())
}

pub(super) fn check_accessors(document: &Document, buffers: &[BufferData]) -> Loaded<()> {
    for accessor in document.accessors() {
        check_accessor(&accessor, buffers)
            .map_err(|problem| format!("accessor {}: {problem}", accessor.index()))?;
    }
    Ok(())
}

/// Checks that every element the crate will read lies inside the buffer view.
fn check_accessor(accessor: &Accessor, buffers: &[BufferData]) -> Loaded<()> {
    let count = accessor.count();
    if count == 0 {
        return Err("count is 0".into());
    }
    let element_size = accessor.size();
    match accessor.view() {
        Some(view) => check_strided_range("data", &view, accessor.offset(), element_size, count)?,
        None if count.saturating_mul(element_size) > MAX_ZERO_FILLED_BYTES => {
            return Err(format!(
                "count {count} of {element_size}-byte elements without a buffer view \
                 (at most {} MiB of zeros are accepted)",
                MAX_ZERO_FILLED_BYTES >> 20
            ));
        }
        None => {}
    }
    if let Some(sparse) = accessor.sparse() {
        check_sparse(&sparse, count, element_size, buffers)?;
    }
    Ok(())
}

/// `count` elements of `element_size` bytes, `stride` apart (the view's
/// `byteStride`, else packed), from `offset`, must fit in `view`.
fn check_strided_range(
    what: &str,
    view: &gltf::buffer::View,
    offset: usize,
    element_size: usize,
    count: usize,
) -> Loaded<()> {
    let stride = view.stride().unwrap_or(element_size);
    if stride < element_size {
        return Err(format!(
            "{what}: byteStride {stride} is smaller than the element size {element_size}"
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|span| span.checked_add(offset))
        .and_then(|span| span.checked_add(element_size));
    if end.is_some_and(|end| end <= view.length()) {
        Ok(())
    } else {
        Err(format!(
            "{what}: {count} elements of {element_size} bytes (stride {stride}) from byte \
             {offset} do not fit buffer view {} ({} bytes)",
            view.index(),
            view.length()
        ))
    }
}

fn check_sparse(
    sparse: &gltf::accessor::sparse::Sparse,
    count: usize,
    element_size: usize,
    buffers: &[BufferData],
) -> Loaded<()> {
    let sparse_count = sparse.count();
    if sparse_count == 0 || sparse_count > count {
        return Err(format!(
            "sparse count {sparse_count} must lie between 1 and the accessor count {count}"
        ));
    }
    let indices = sparse.indices();
    let index_size = indices.index_type().size();
    check_strided_range(
        "sparse indices",
        &indices.view(),
        indices.offset(),
        index_size,
        sparse_count,
    )?;
    let values = sparse.values();
    check_strided_range(
        "sparse values",
        &values.view(),
        values.offset(),
        element_size,
        sparse_count,
    )?;
    check_sparse_indices(&indices, sparse_count, count, buffers)
}

/// Sparse indices must be strictly increasing and below the accessor count
/// (the crate silently drops values otherwise).
fn check_sparse_indices(
    indices: &gltf::accessor::sparse::Indices,
    sparse_count: usize,
    count: usize,
    buffers: &[BufferData],
) -> Loaded<()> {
    let view = indices.view();
    let data = &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()];
    let size = indices.index_type().size();
    let stride = view.stride().unwrap_or(size);
    let mut previous = None;
    for k in 0..sparse_count {
        let at = indices.offset() + k * stride;
        let index = data[at..at + size]
            .iter()
            .rev()
            .fold(0usize, |value, &byte| (value << 8) | usize::from(byte));
        if index >= count {
            return Err(format!(
                "sparse index {index} out of range ({count} elements)"
            ));
        }
        if previous.is_some_and(|previous| index <= previous) {
            return Err("sparse indices are not strictly increasing".into());
        }
        previous = Some(index);
    }
    Ok(())
}

/// Reads every element of `accessor` as `T` (whose layout the caller has
/// checked); an accessor without buffer view or sparse data holds zeros.
pub(super) fn read_accessor<T: Item + Clone>(
    accessor: &Accessor,
    buffers: &[BufferData],
) -> Loaded<Vec<T>> {
    if accessor.view().is_none() && accessor.sparse().is_none() {
        return Ok(vec![T::zero(); accessor.count()]);
    }
    let buffer_data = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(|data| &data[..]);
    let items: Vec<T> = gltf::accessor::Iter::new(accessor.clone(), buffer_data)
        .ok_or_else(|| format!("accessor {}: data out of range", accessor.index()))?
        .collect();
    if items.len() != accessor.count() {
        return Err(format!(
            "accessor {}: read {} elements instead of {}",
            accessor.index(),
            items.len(),
            accessor.count()
        ));
    }
    Ok(items)
}

/// e.g. "VEC3 of FLOAT".
pub(super) fn layout_name(accessor: &Accessor) -> String {
    let dimensions = match accessor.dimensions() {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    };
    let component = match accessor.data_type() {
        DataType::I8 => "BYTE",
        DataType::U8 => "UNSIGNED_BYTE",
        DataType::I16 => "SHORT",
        DataType::U16 => "UNSIGNED_SHORT",
        DataType::U32 => "UNSIGNED_INT",
        DataType::F32 => "FLOAT",
    };
    format!("{dimensions} of {component}")
}

pub(super) fn is_vec3_of_float(accessor: &Accessor) -> bool {
    accessor.dimensions() == Dimensions::Vec3 && accessor.data_type() == DataType::F32
}
