//! Reading a glTF file: the `.glb` container, URIs and files, buffers and accessors, each offset and length checked before use.

use super::*;

/// Largest number of components an accessor without a buffer view (all zeros) may have.
pub(super) const MAX_ZERO_COMPONENTS: usize = 1 << 28;

pub(super) fn import_impl(
    bytes: &[u8],
    fallback_name: &str,
    base: Option<&Path>,
) -> Result<(Scene, Vec<String>), String> {
    let (json_bytes, bin) = if bytes.starts_with(b"glTF") {
        split_glb(bytes)?
    } else {
        (bytes, None)
    };
    let root: gltf::json::Root = gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| format!("the glTF JSON is malformed: {e}"))?;
    prevalidate(&root)?;
    let doc = gltf::Document::from_json(root).map_err(describe_gltf_error)?;
    let buffers = load_buffers(&doc, bin, base)?;
    Importer {
        doc: &doc,
        buffers,
        base,
        objects: vec![],
        pending: vec![],
        lights: vec![],
        camera: None,
        notes: vec![],
        triangles: 0,
        cut_out: 0,
    }
    .run(fallback_name)
}

/// Checks what the `gltf` crate's own validation would index without checking: its
/// primitive hook reads `accessors[POSITION]` directly (gltf-json 1.4.1, mesh.rs) and
/// panics when that index is out of range.
pub(super) fn prevalidate(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "an attribute".into(),
                    };
                    return Err(format!(
                        "mesh {m} primitive {p} uses accessor {} for {name}, but there are only {} accessors",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    Ok(())
}

pub(super) fn describe_gltf_error(e: gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => {
            let shown: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(path, err)| format!("{path}: {err}"))
                .collect();
            let more = if errors.len() > 3 {
                format!(" (and {} more)", errors.len() - 3)
            } else {
                String::new()
            };
            format!("the glTF does not validate: {}{more}", shown.join("; "))
        }
        other => format!("the glTF cannot be read: {other}"),
    }
}

/// Splits a `.glb` into its JSON and optional BIN chunks, checking every length.
pub(super) fn split_glb(b: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |o: usize| -> Option<usize> {
        b.get(o..o + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize)
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!(
            "the .glb file is truncated: {} bytes is shorter than its 12-byte header",
            b.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "the .glb container has version {version}; only version 2 is supported"
        ));
    }
    if length > b.len() {
        return Err(format!(
            "the .glb file is truncated: its header declares {length} bytes but only {} are present",
            b.len()
        ));
    }
    if length < 20 {
        return Err(format!(
            "the .glb header declares a length of {length} bytes, too short for a JSON chunk"
        ));
    }
    let b = &b[..length];
    let (mut json, mut bin) = (None, None);
    let mut pos = 12;
    while pos < length {
        let (Some(chunk_len), Some(kind)) = (word(pos), word(pos + 4)) else {
            return Err(format!(
                "the .glb file is truncated inside the chunk header at byte {pos}"
            ));
        };
        let start = pos + 8;
        let end = start.checked_add(chunk_len).filter(|&e| e <= length).ok_or_else(|| {
            format!("the .glb chunk at byte {pos} declares {chunk_len} bytes, past the end of the file (truncated?)")
        })?;
        match kind {
            0x4E4F_534A if json.is_none() && pos == 12 => json = Some(&b[start..end]),
            0x004E_4942 if json.is_some() && bin.is_none() => bin = Some(&b[start..end]),
            _ if pos == 12 => return Err("the first .glb chunk is not the JSON chunk".into()),
            _ => {} // unknown chunks are ignored, as the spec asks
        }
        pos = end;
    }
    let json = json.ok_or("the .glb file has no JSON chunk")?;
    Ok((json, bin))
}

/// Reads the bytes a URI points at: a base64 `data:` URI, or a file relative to `base`.
///
/// A file must be a regular file inside `base` once `..` and symbolic links are resolved
/// (absolute paths, `../`, `%2e%2e/` and links out of the folder are refused, so a glTF file
/// cannot make the importer read `/etc/passwd`), and at most `limit` bytes are read from it.
pub(super) fn read_uri(
    uri: &str,
    base: Option<&Path>,
    what: &str,
    limit: u64,
    first_bytes: bool,
) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or_else(|| format!("{what} has a data URI that is not base64"))?;
        return base64_decode(payload)
            .map_err(|e| format!("{what} has a malformed base64 data URI: {e}"));
    }
    let shown = printable(uri);
    if uri.contains(':') {
        return Err(format!(
            "{what} refers to \"{shown}\", whose URI scheme is not supported (only data: URIs and relative paths)"
        ));
    }
    let relative =
        percent_decode(uri).ok_or_else(|| format!("{what} has a malformed URI \"{shown}\""))?;
    if relative.chars().any(char::is_control) {
        return Err(format!(
            "{what} refers to \"{}\", a file name with control characters",
            printable(&relative)
        ));
    }
    let Some(base) = base else {
        return Err(format!(
            "{what} refers to the external file \"{relative}\", which cannot be resolved when importing from memory"
        ));
    };
    if Path::new(&relative).has_root() {
        return Err(format!(
            "{what} refers to the absolute path \"{relative}\"; only files inside the glTF's folder are read"
        ));
    }
    let outside = || {
        format!(
            "{what} refers to \"{relative}\", outside the glTF's folder; only files inside it are read"
        )
    };
    let folder = base
        .canonicalize()
        .map_err(|e| format!("the glTF's folder {} cannot be read: {e}", shown_path(base)))?;
    let full = base.join(&relative);
    let resolved = match full.canonicalize() {
        Ok(p) => p,
        // A missing file: say so, unless the name climbs out of the folder.
        Err(_) if relative.split(['/', '\\']).any(|c| c == "..") => return Err(outside()),
        Err(e) => {
            return Err(format!(
                "{what} refers to {}, which cannot be read: {e}",
                shown_path(&full)
            ));
        }
    };
    if !resolved.starts_with(&folder) {
        return Err(outside());
    }
    read_regular_file(&resolved, limit, first_bytes, true).map_err(|e| {
        format!(
            "{what} refers to {}, which cannot be read: {e}",
            shown_path(&full)
        )
    })
}

/// Decodes the base64 payload of a `data:` URI: the standard or the URL-safe alphabet, with
/// or without padding, whitespace ignored (writers differ).
pub(super) fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    static LENIENT: std::sync::OnceLock<data_encoding::Encoding> = std::sync::OnceLock::new();
    let encoding = LENIENT.get_or_init(|| {
        let mut spec = data_encoding::BASE64_NOPAD.specification();
        spec.translate.from.push_str("-_");
        spec.translate.to.push_str("+/");
        spec.ignore.push_str(" \t\r\n");
        spec.check_trailing_bits = false;
        spec.encoding().expect("a valid base64 specification")
    });
    let unpadded = text.trim_end_matches(|c: char| c == '=' || c.is_ascii_whitespace());
    encoding
        .decode(unpadded.as_bytes())
        .map_err(|e| e.to_string())
}

pub(super) fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

pub(super) fn load_buffers(
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    base: Option<&Path>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut bin = bin;
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let what = format!("buffer {}", buffer.index());
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => bin
                .take()
                .ok_or_else(|| format!("{what} refers to the .glb binary chunk, which is missing"))?
                .to_vec(),
            // No more than the declared length is read: the rest of a file is not the buffer.
            gltf::buffer::Source::Uri(uri) => read_uri(
                uri,
                base,
                &what,
                (buffer.length() as u64).min(MAX_FILE_BYTES),
                true,
            )?,
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "{what} holds {} bytes but declares a byteLength of {} (truncated?)",
                data.len(),
                buffer.length()
            ));
        }
        out.push(data);
    }
    Ok(out)
}

pub(super) fn view_bytes<'b>(
    buffers: &'b [Vec<u8>],
    view: &gltf::buffer::View,
) -> Result<&'b [u8], String> {
    let index = view.buffer().index();
    let buf = buffers
        .get(index)
        .ok_or_else(|| format!("buffer view {} uses missing buffer {index}", view.index()))?;
    let start = view.offset();
    start
        .checked_add(view.length())
        .and_then(|end| buf.get(start..end))
        .ok_or_else(|| {
            format!(
                "buffer view {} (offset {start}, {} bytes) lies outside buffer {index} ({} bytes)",
                view.index(),
                view.length(),
                buf.len()
            )
        })
}

pub(super) fn component_f32(b: &[u8], ty: gltf::accessor::DataType, normalized: bool) -> f32 {
    use gltf::accessor::DataType::*;
    match (ty, normalized) {
        (F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (U8, false) => b[0] as f32,
        (U8, true) => b[0] as f32 / 255.0,
        (I8, false) => b[0] as i8 as f32,
        (I8, true) => (b[0] as i8 as f32 / 127.0).max(-1.0),
        (U16, false) => u16::from_le_bytes([b[0], b[1]]) as f32,
        (U16, true) => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        (I16, false) => i16::from_le_bytes([b[0], b[1]]) as f32,
        (I16, true) => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        (U32, false) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        (U32, true) => {
            (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64 / u32::MAX as f64) as f32
        }
    }
}

pub(super) fn component_u32(b: &[u8], ty: gltf::accessor::DataType) -> u32 {
    match b.len() {
        1 => b[0] as u32,
        2 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ if ty == gltf::accessor::DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        _ => 0,
    }
}

/// Reads every component of `acc` (count * components values) with `conv`, checking every
/// offset against the buffer view and applying sparse substitution.
pub(super) fn read_accessor<T: Copy + Default>(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    conv: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, String> {
    let index = acc.index();
    let count = acc.count();
    let ncomp = acc.dimensions().multiplicity();
    let csize = acc.data_type().size();
    let elem = ncomp * csize;
    let total = count
        .checked_mul(ncomp)
        .ok_or_else(|| format!("accessor {index} ({what}) has an impossible count {count}"))?;
    let range_err = |need: Option<usize>, view: usize, have: usize| {
        format!(
            "accessor {index} ({what}) is out of range: it needs {} bytes of buffer view {view}, which has {have}",
            need.map(|n| n.to_string())
                .unwrap_or_else(|| "more than addressable".into())
        )
    };
    let mut out = match acc.view() {
        Some(view) => {
            let bytes = view_bytes(buffers, &view)?;
            let stride = view.stride().unwrap_or(elem);
            if stride < elem {
                return Err(format!(
                    "accessor {index} ({what}) has elements of {elem} bytes but buffer view {} has a stride of {stride}",
                    view.index()
                ));
            }
            let start = acc.offset();
            let need = if count == 0 {
                Some(start)
            } else {
                stride
                    .checked_mul(count - 1)
                    .and_then(|s| s.checked_add(start))
                    .and_then(|s| s.checked_add(elem))
            };
            if need.is_none_or(|n| n > bytes.len()) {
                return Err(range_err(need, view.index(), bytes.len()));
            }
            let mut out = Vec::with_capacity(total);
            for i in 0..count {
                let e = start + i * stride;
                for c in 0..ncomp {
                    let o = e + c * csize;
                    out.push(conv(&bytes[o..o + csize]));
                }
            }
            out
        }
        None => {
            if total > MAX_ZERO_COMPONENTS {
                return Err(format!(
                    "accessor {index} ({what}) has no data and an implausible count {count}"
                ));
            }
            vec![T::default(); total]
        }
    };
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        let indices = sparse.indices();
        let iview = indices.view();
        let ibytes = view_bytes(buffers, &iview)?;
        let isize = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let istart = indices.offset();
        let ineed = n.checked_mul(isize).and_then(|s| s.checked_add(istart));
        if ineed.is_none_or(|x| x > ibytes.len()) {
            return Err(range_err(ineed, iview.index(), ibytes.len()));
        }
        let values = sparse.values();
        let vview = values.view();
        let vbytes = view_bytes(buffers, &vview)?;
        let vstart = values.offset();
        let vneed = n.checked_mul(elem).and_then(|s| s.checked_add(vstart));
        if vneed.is_none_or(|x| x > vbytes.len()) {
            return Err(range_err(vneed, vview.index(), vbytes.len()));
        }
        for j in 0..n {
            let io = istart + j * isize;
            let target =
                component_u32(&ibytes[io..io + isize], gltf::accessor::DataType::U32) as usize;
            if target >= count {
                return Err(format!(
                    "accessor {index} ({what}) has sparse index {target}, out of range for its {count} elements"
                ));
            }
            for c in 0..ncomp {
                let o = vstart + j * elem + c * csize;
                out[target * ncomp + c] = conv(&vbytes[o..o + csize]);
            }
        }
    }
    Ok(out)
}

pub(super) fn read_floats(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    dims: gltf::accessor::Dimensions,
) -> Result<Vec<f32>, String> {
    if acc.dimensions() != dims {
        return Err(format!(
            "accessor {} ({what}) is {:?}, expected {:?}",
            acc.index(),
            acc.dimensions(),
            dims
        ));
    }
    let (ty, normalized) = (acc.data_type(), acc.normalized());
    read_accessor(acc, buffers, what, |b| component_f32(b, ty, normalized))
}

pub(super) fn read_indices(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    what: &str,
) -> Result<Vec<u32>, String> {
    use gltf::accessor::DataType::*;
    let ty = acc.data_type();
    if acc.dimensions() != gltf::accessor::Dimensions::Scalar
        || !matches!(ty, U8 | U16 | U32)
        || acc.normalized()
    {
        return Err(format!(
            "accessor {} ({what}) is not a scalar unsigned-integer index accessor",
            acc.index()
        ));
    }
    read_accessor(acc, buffers, what, |b| component_u32(b, ty))
}
