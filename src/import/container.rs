//! The containers an OpenRocket design comes in: plain XML (0.9 and later), gzip-compressed
//! XML (1.0 to 15.03 saved `.ork` files gzipped by default) and ZIP archives (15.03 and later:
//! the design as `rocket.ork` beside decals and attachments). RockSim `.rkt` files are plain
//! XML too; the caller tells them apart by their root element.

use std::io::Read;

/// What went wrong opening a container.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ContainerError(pub String);

/// The design document inside `bytes`: its XML text and, for a ZIP archive, the entry it was
/// read from.
pub fn decode(bytes: &[u8]) -> Result<(String, Option<String>), ContainerError> {
    if bytes.starts_with(b"PK\x03\x04") || bytes.starts_with(b"PK\x05\x06") {
        return unzip(bytes);
    }
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(bytes)
            .read_to_end(&mut out)
            .map_err(|e| ContainerError(format!("corrupt or truncated gzip stream: {e}")))?;
        return text(out).map(|t| (t, None));
    }
    text(bytes.to_vec()).map(|t| (t, None))
}

fn text(bytes: Vec<u8>) -> Result<String, ContainerError> {
    if bytes.is_empty() {
        return Err(ContainerError("the file is empty".into()));
    }
    String::from_utf8(bytes).map_err(|e| {
        ContainerError(format!(
            "not a design file: neither ZIP, gzip nor UTF-8 XML (invalid UTF-8 at byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// The design entry of an OpenRocket ZIP archive: `rocket.ork` where present (what OpenRocket
/// writes), else the only `.ork`/`.rkt`/`.xml` entry.
fn unzip(bytes: &[u8]) -> Result<(String, Option<String>), ContainerError> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| ContainerError(format!("corrupt or truncated ZIP archive: {e}")))?;
    let names: Vec<String> = zip.file_names().map(str::to_string).collect();
    let is_design = |n: &str| {
        let l = n.to_ascii_lowercase();
        l.ends_with(".ork") || l.ends_with(".rkt") || l.ends_with(".xml")
    };
    let pick = names
        .iter()
        .find(|n| n.eq_ignore_ascii_case("rocket.ork"))
        .cloned()
        .or_else(|| {
            let c: Vec<&String> = names.iter().filter(|n| is_design(n)).collect();
            (c.len() == 1).then(|| c[0].clone())
        })
        .ok_or_else(|| {
            ContainerError(format!(
                "the ZIP archive holds no design (`rocket.ork`); its entries: {}",
                names.join(", ")
            ))
        })?;
    let mut f = zip
        .by_name(&pick)
        .map_err(|e| ContainerError(format!("cannot open `{pick}` in the archive: {e}")))?;
    let mut out = Vec::new();
    f.read_to_end(&mut out)
        .map_err(|e| ContainerError(format!("corrupt or truncated entry `{pick}`: {e}")))?;
    // A stored design may itself be gzipped (files converted from 1.x).
    if out.starts_with(&[0x1f, 0x8b]) {
        let mut inner = Vec::new();
        flate2::read::GzDecoder::new(&out[..])
            .read_to_end(&mut inner)
            .map_err(|e| ContainerError(format!("corrupt gzip stream in `{pick}`: {e}")))?;
        out = inner;
    }
    text(out).map(|t| (t, Some(pick)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn plain_gzip_and_zip_give_the_same_text() {
        let xml = "<openrocket version=\"1.0\"/>";
        assert_eq!(decode(xml.as_bytes()).unwrap().0, xml);
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(xml.as_bytes()).unwrap();
        let gz = gz.finish().unwrap();
        assert_eq!(decode(&gz).unwrap().0, xml);
        let mut buf = std::io::Cursor::new(Vec::new());
        {
            let mut z = zip::ZipWriter::new(&mut buf);
            z.start_file("decals/x.png", zip::write::SimpleFileOptions::default())
                .unwrap();
            z.write_all(b"png").unwrap();
            z.start_file("rocket.ork", zip::write::SimpleFileOptions::default())
                .unwrap();
            z.write_all(xml.as_bytes()).unwrap();
            z.finish().unwrap();
        }
        let (t, entry) = decode(buf.get_ref()).unwrap();
        assert_eq!(t, xml);
        assert_eq!(entry.as_deref(), Some("rocket.ork"));
    }

    #[test]
    fn truncated_containers_are_errors() {
        let xml = "<openrocket version=\"1.0\"><rocket/></openrocket>".repeat(50);
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(xml.as_bytes()).unwrap();
        let gz = gz.finish().unwrap();
        assert!(decode(&gz[..gz.len() / 2]).is_err());
        let mut buf = std::io::Cursor::new(Vec::new());
        {
            let mut z = zip::ZipWriter::new(&mut buf);
            z.start_file("rocket.ork", zip::write::SimpleFileOptions::default())
                .unwrap();
            z.write_all(xml.as_bytes()).unwrap();
            z.finish().unwrap();
        }
        let b = buf.get_ref();
        assert!(decode(&b[..b.len() / 2]).is_err());
        assert!(decode(b"").is_err());
        assert!(decode(&[0xff, 0xfe, 0x00]).is_err());
    }
}
