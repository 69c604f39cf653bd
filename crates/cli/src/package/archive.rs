//! Writing the `.fmu` archive: a deflated zip of modelDescription.xml, the binaries and the
//! documentation, byte-identical when rebuilt from the same inputs; and any such zip
//! ([`write_zip`], an SSP's).

use std::io::{Seek, Write};
use std::path::Path;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// What goes into an FMU.
pub struct Contents<'a> {
    pub model_description: &'a str,
    /// The shared libraries (path inside the archive, `binaries/<platform>/<id>.<ext>`, and
    /// bytes).
    pub binaries: Vec<(String, Vec<u8>)>,
    /// Extra files (path inside the archive, bytes), e.g. `documentation/index.html`.
    pub extra: Vec<(String, Vec<u8>)>,
}

/// Writes the archive to `path` (through a temporary file, so a failed write never leaves
/// a truncated FMU behind).
pub fn write_fmu(path: &Path, contents: &Contents) -> std::io::Result<()> {
    write_zip(path, &fmu_entries(contents))
}

/// The files of an FMU, `modelDescription.xml` first.
fn fmu_entries<'a>(contents: &'a Contents) -> Vec<(String, &'a [u8])> {
    let mut entries: Vec<(String, &[u8])> = vec![(
        "modelDescription.xml".into(),
        contents.model_description.as_bytes(),
    )];
    entries.extend(
        contents
            .binaries
            .iter()
            .chain(&contents.extra)
            .map(|(p, b)| (p.clone(), b.as_slice())),
    );
    entries
}

/// Writes a deflated zip of `entries` (path inside the archive, bytes), in their order and
/// with the folders they need, to `path` through a temporary file beside it.
pub fn write_zip(path: &Path, entries: &[(String, &[u8])]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let file = std::fs::File::create(&tmp)?;
    write_archive(std::io::BufWriter::new(file), entries)?;
    std::fs::rename(&tmp, path)
}

fn write_archive<W: Write + Seek>(writer: W, entries: &[(String, &[u8])]) -> std::io::Result<()> {
    let mut zip = ZipWriter::new(writer);
    // A fixed timestamp and fixed permissions: the archive depends on its contents only.
    let file = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(DateTime::default())
        .unix_permissions(0o644);
    let dir = file.unix_permissions(0o755);
    let mut dirs: Vec<String> = Vec::new();
    for (path, bytes) in entries {
        let mut prefix = String::new();
        for part in path
            .split('/')
            .collect::<Vec<_>>()
            .split_last()
            .map_or(&[][..], |(_, d)| d)
        {
            prefix.push_str(part);
            prefix.push('/');
            if !dirs.contains(&prefix) {
                zip.add_directory(prefix.clone(), dir)
                    .map_err(std::io::Error::other)?;
                dirs.push(prefix.clone());
            }
        }
        zip.start_file(path.as_str(), file)
            .map_err(std::io::Error::other)?;
        zip.write_all(bytes)?;
    }
    zip.finish().map_err(std::io::Error::other)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn archive(xml: &str) -> Vec<u8> {
        let mut buf = std::io::Cursor::new(Vec::new());
        let contents = Contents {
            model_description: xml,
            binaries: vec![
                (
                    "binaries/linux64/Test.so".into(),
                    b"\x7fELF binary".to_vec(),
                ),
                ("binaries/win64/Test.dll".into(), b"MZ binary".to_vec()),
            ],
            extra: vec![("documentation/index.html".into(), b"<html/>".to_vec())],
        };
        write_archive(&mut buf, &fmu_entries(&contents)).unwrap();
        buf.into_inner()
    }

    #[test]
    fn archive_is_deterministic_and_complete() {
        let a = archive("<fmiModelDescription/>");
        assert_eq!(a, archive("<fmiModelDescription/>"));
        assert_ne!(a, archive("<fmiModelDescription />"));
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
        let names: Vec<String> = (0..zip.len())
            .map(|i| zip.by_index(i).unwrap().name().unwrap().to_string())
            .collect();
        for name in [
            "modelDescription.xml",
            "binaries/linux64/Test.so",
            "binaries/win64/Test.dll",
            "documentation/index.html",
        ] {
            assert!(
                names.contains(&name.to_string()),
                "{name} missing from {names:?}"
            );
        }
        let so = zip.by_name("binaries/linux64/Test.so").unwrap();
        assert_eq!(so.compression(), CompressionMethod::Deflated);
    }
}
