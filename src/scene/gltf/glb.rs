//! The binary container (GLB): a 12-byte header, then chunks (JSON first, then
//! an optional BIN), every declared length checked against the bytes present.

use super::Loaded;

const MAGIC: &[u8; 4] = b"glTF";
const HEADER_LEN: usize = 12;
const CHUNK_HEADER_LEN: usize = 8;
const JSON: [u8; 4] = *b"JSON";
const BIN: [u8; 4] = *b"BIN\0";

pub(super) fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Splits a GLB file into its JSON chunk and its BIN chunk (if any),
/// checking every declared length against the bytes really present.
pub(super) fn split(bytes: &[u8]) -> Loaded<(&[u8], Option<&[u8]>)> {
    if bytes.len() < HEADER_LEN {
        return Err(format!(
            "GLB file of {} bytes is shorter than its 12-byte header",
            bytes.len()
        ));
    }
    let version = read_u32(bytes, 4);
    if version != 2 {
        return Err(format!("GLB version {version} is not supported (only 2)"));
    }
    let total = read_u32(bytes, 8) as usize;
    if total > bytes.len() {
        return Err(format!(
            "GLB header declares {total} bytes but the file has only {}",
            bytes.len()
        ));
    }
    if total < HEADER_LEN + CHUNK_HEADER_LEN {
        return Err(format!(
            "GLB header declares {total} bytes, too few for a JSON chunk (at least 20)"
        ));
    }
    let mut chunks = Chunks {
        bytes: &bytes[..total],
        offset: HEADER_LEN,
        number: 0,
    };
    let json = match chunks.next_chunk()? {
        Some((JSON, data)) => data,
        Some((kind, _)) => {
            return Err(format!(
                "the first GLB chunk must be JSON, not {:?}",
                String::from_utf8_lossy(&kind)
            ));
        }
        None => return Err("GLB file has no JSON chunk".into()),
    };
    let mut bin = None;
    while let Some((kind, data)) = chunks.next_chunk()? {
        // chunks of unknown types are skipped, as the specification asks
        if kind == BIN && bin.is_none() {
            bin = Some(data);
        }
    }
    Ok((json, bin))
}

struct Chunks<'a> {
    bytes: &'a [u8],
    offset: usize,
    number: usize,
}

impl<'a> Chunks<'a> {
    fn next_chunk(&mut self) -> Loaded<Option<([u8; 4], &'a [u8])>> {
        let remaining = self.bytes.len() - self.offset;
        if remaining == 0 {
            return Ok(None);
        }
        if remaining < CHUNK_HEADER_LEN {
            return Err(format!(
                "GLB chunk {} header is truncated ({remaining} of 8 bytes)",
                self.number
            ));
        }
        let length = read_u32(self.bytes, self.offset) as usize;
        let mut kind = [0; 4];
        kind.copy_from_slice(&self.bytes[self.offset + 4..self.offset + 8]);
        let start = self.offset + CHUNK_HEADER_LEN;
        if length > self.bytes.len() - start {
            return Err(format!(
                "GLB chunk {} ({:?}) declares {length} bytes but only {} remain",
                self.number,
                String::from_utf8_lossy(&kind),
                self.bytes.len() - start
            ));
        }
        self.offset = start + length;
        self.number += 1;
        Ok(Some((kind, &self.bytes[start..start + length])))
    }
}

fn read_u32(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}
