//! Zip archives and XML documents from outside, read with limits: KMZ, shapefile zips, ISOXML
//! TaskData. A file that would unpack past the limit (a zip bomb) or declares XML entities is
//! refused before anything else reads it.

use std::io::{Cursor, Read, Write};

use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipArchive, ZipWriter};

use super::error::InputError;

/// Most bytes the entries of one uploaded archive may unpack to.
pub const MAX_UNPACKED_BYTES: u64 = 64 * 1024 * 1024;
/// Most entries in one uploaded archive.
pub const MAX_ENTRIES: usize = 1_000;

/// True when `bytes` start like a zip archive (a local file header or an empty archive).
pub fn is_zip(bytes: &[u8]) -> bool {
    bytes.starts_with(b"PK\x03\x04") || bytes.starts_with(b"PK\x05\x06")
}

/// The files of a zip archive, by name, each read whole; directories are left out.
pub fn unzip(bytes: &[u8]) -> Result<Vec<(String, Vec<u8>)>, InputError> {
    let broken = |e: zip::result::ZipError| InputError::new("invalid_zip", "/", format!("not a readable zip archive: {e}"));
    let mut archive = ZipArchive::new(Cursor::new(bytes)).map_err(broken)?;
    if archive.len() > MAX_ENTRIES {
        return Err(InputError::new("archive_too_large", "/", format!("the archive holds {} entries; the limit is {MAX_ENTRIES}", archive.len())));
    }
    let mut files = Vec::new();
    let mut unpacked = 0u64;
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).map_err(broken)?;
        if entry.is_dir() {
            continue;
        }
        let name = String::from_utf8_lossy(entry.name_raw()).into_owned();
        // the declared size can lie: read at most what is left of the budget, plus one byte
        let budget = MAX_UNPACKED_BYTES - unpacked;
        let mut content = Vec::new();
        (&mut entry).take(budget + 1).read_to_end(&mut content).map_err(|e| InputError::new("invalid_zip", format!("/{name}"), format!("this entry cannot be unpacked: {e}")))?;
        unpacked += content.len() as u64;
        if unpacked > MAX_UNPACKED_BYTES {
            return Err(InputError::new(
                "archive_too_large",
                format!("/{name}"),
                format!("the archive unpacks to more than {} MB; the limit protects the service from zip bombs", MAX_UNPACKED_BYTES / 1024 / 1024),
            ));
        }
        files.push((name, content));
    }
    Ok(files)
}

/// A zip archive of `files` (name, content), deflated.
pub fn zip(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut writer = ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    for (name, content) in files {
        // writing to memory cannot fail
        writer.start_file(name.as_str(), options).expect("zip entry in memory");
        writer.write_all(content).expect("zip entry in memory");
    }
    writer.finish().expect("zip in memory").into_inner()
}

/// The text of an XML document, refused when it declares a document type or entities: external
/// entities could read the server's files, and nested ones expand without bound.
pub fn xml_text<'a>(bytes: &'a [u8], part: &str) -> Result<&'a str, InputError> {
    let text = std::str::from_utf8(bytes).map_err(|e| InputError::new("invalid_xml", part, format!("the XML is not UTF-8: {e}")))?;
    let text = text.trim_start_matches('\u{feff}');
    if text.contains("<!DOCTYPE") || text.contains("<!ENTITY") {
        return Err(InputError::new("xml_entities_refused", part, "the XML declares a document type or entities; they are refused (they can read files or expand without bound)"));
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zips_and_unzips() {
        let files = vec![("a/doc.kml".to_owned(), b"hello".to_vec()), ("b.txt".to_owned(), vec![7; 10_000])];
        let bytes = zip(&files);
        assert!(is_zip(&bytes));
        assert_eq!(unzip(&bytes).unwrap(), files);
    }

    #[test]
    fn refuses_a_bomb() {
        // 65 MB of zeros deflate to about 64 kB
        let bomb = zip(&[("zeros".to_owned(), vec![0; (MAX_UNPACKED_BYTES + 1024 * 1024) as usize])]);
        assert!(bomb.len() < 1024 * 1024);
        assert_eq!(unzip(&bomb).unwrap_err().code, "archive_too_large");
    }

    #[test]
    fn refuses_entities() {
        let xxe = br#"<?xml version="1.0"?><!DOCTYPE kml [<!ENTITY x SYSTEM "file:///etc/passwd">]><kml>&x;</kml>"#;
        assert_eq!(xml_text(xxe, "/doc.kml").unwrap_err().code, "xml_entities_refused");
        assert!(xml_text(b"<kml/>", "/doc.kml").is_ok());
        assert_eq!(unzip(b"PK\x03\x04 not really").unwrap_err().code, "invalid_zip");
    }
}
