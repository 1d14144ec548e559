//! Whether a file is whole before it is decoded: decoders stop once they have the pixels (a PNG
//! without its end chunk decodes, so does a GIF cut after its first frame) or fill a missing tail
//! with grey and report success (JPEG), so a file cut short would be painted as if it were whole.
//! Each check walks the format's own structure to its end marker and names where the file stops.

/// Checks that a JPEG's segments and entropy-coded scans run to its end-of-image marker (EOI),
/// walking the markers (lengths of header segments, stuffed bytes and restart markers inside
/// scans); anything after the EOI is ignored. A file cut anywhere after its first bytes loses
/// the EOI and is refused as truncated; an embedded thumbnail's EOI inside an APP segment is
/// skipped with its segment.
pub fn jpeg_is_whole(bytes: &[u8]) -> std::result::Result<(), String> {
    let truncated = |at: usize| {
        Err(format!(
            "truncated JPEG: no end-of-image marker (the file ends at byte {at}, inside a segment or scan)"
        ))
    };
    if bytes.len() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8 {
        return Err("not a JPEG (no start-of-image marker)".into());
    }
    let mut i = 2;
    loop {
        // Fill bytes (0xFF) may precede a marker.
        while i < bytes.len() && bytes[i] == 0xFF && bytes.get(i + 1) == Some(&0xFF) {
            i += 1;
        }
        if i + 1 >= bytes.len() {
            return truncated(bytes.len());
        }
        if bytes[i] != 0xFF {
            return Err(format!("corrupt JPEG: expected a marker at byte {i}"));
        }
        let marker = bytes[i + 1];
        match marker {
            0xD9 => return Ok(()),
            0x01 | 0xD0..=0xD7 => i += 2,
            _ => {
                if i + 3 >= bytes.len() {
                    return truncated(bytes.len());
                }
                let length = usize::from(u16::from_be_bytes([bytes[i + 2], bytes[i + 3]]));
                if length < 2 {
                    return Err(format!("corrupt JPEG: segment length {length} at byte {i}"));
                }
                i += 2 + length;
                if i > bytes.len() {
                    return truncated(bytes.len());
                }
                if marker == 0xDA {
                    // Entropy-coded data runs to the next marker that is not a stuffed 0xFF00
                    // or a restart marker.
                    loop {
                        match bytes[i..].iter().position(|&b| b == 0xFF) {
                            None => return truncated(bytes.len()),
                            Some(k) => i += k,
                        }
                        match bytes.get(i + 1) {
                            None => return truncated(bytes.len()),
                            Some(0x00 | 0xD0..=0xD7) => i += 2,
                            Some(_) => break,
                        }
                    }
                }
            }
        }
    }
}

/// Checks that a PNG's chunks (length, type, data, CRC) run whole to its `IEND` chunk;
/// anything after `IEND` is ignored.
pub fn png_is_whole(bytes: &[u8]) -> std::result::Result<(), String> {
    let truncated = |at: usize| {
        Err(format!(
            "truncated PNG: the file ends at byte {at}, before its IEND end chunk"
        ))
    };
    let mut pos = 8; // the signature
    loop {
        let Some(header) = bytes.get(pos..pos + 8) else {
            return truncated(bytes.len());
        };
        let len = u32::from_be_bytes([header[0], header[1], header[2], header[3]]) as usize;
        let end = pos.saturating_add(12).saturating_add(len);
        if end > bytes.len() {
            return truncated(bytes.len());
        }
        if &header[4..8] == b"IEND" {
            return Ok(());
        }
        pos = end;
    }
}

/// Checks that a GIF's blocks (extensions and images, each with its data sub-blocks) run
/// whole to its trailer (`;`); anything after the trailer is ignored.
pub fn gif_is_whole(bytes: &[u8]) -> std::result::Result<(), String> {
    let truncated = || {
        Err(format!(
            "truncated GIF: the file ends at byte {}, before its trailer",
            bytes.len()
        ))
    };
    let colour_table = |packed: u8| {
        if packed & 0x80 != 0 {
            3usize << ((packed & 7) + 1)
        } else {
            0
        }
    };
    // Header and logical screen descriptor, then the global colour table.
    let Some(&packed) = bytes.get(10) else {
        return truncated();
    };
    let mut pos = 13 + colour_table(packed);
    // Data sub-blocks from `pos`: (size, data)... up to a zero size; the position after.
    let sub_blocks = |mut pos: usize| -> Option<usize> {
        loop {
            let size = *bytes.get(pos)? as usize;
            pos += 1 + size;
            if size == 0 {
                return Some(pos);
            }
        }
    };
    loop {
        let Some(&block) = bytes.get(pos) else {
            return truncated();
        };
        pos = match block {
            b';' => return Ok(()),
            0x21 => match sub_blocks(pos + 2) {
                Some(next) => next,
                None => return truncated(),
            },
            b',' => {
                let Some(&packed) = bytes.get(pos + 9) else {
                    return truncated();
                };
                // Descriptor, local colour table, LZW code size, then the image data.
                match sub_blocks(pos + 10 + colour_table(packed) + 1) {
                    Some(next) => next,
                    None => return truncated(),
                }
            }
            other => return Err(format!("corrupt GIF: block 0x{other:02x} at byte {pos}")),
        };
    }
}
