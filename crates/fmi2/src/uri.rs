//! `fmuResourceLocation` URIs: `file:///abs/path`, `file:/abs/path`, `file://localhost/abs/path`,
//! percent-encoded (RFC 3986), with or without a trailing slash.

use std::path::PathBuf;

/// The folder a `file:` URI names, or a message saying why it is not one.
pub fn file_uri_to_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file:")
        .ok_or_else(|| format!("resource location '{uri}' is not a file: URI"))?;
    let path = if let Some(after) = rest.strip_prefix("//") {
        // file://host/path: only an empty host or localhost name this machine.
        let slash = after.find('/').unwrap_or(after.len());
        let host = &after[..slash];
        if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
            return Err(format!("resource location '{uri}' names another host '{host}'"));
        }
        &after[slash..]
    } else {
        rest
    };
    if !path.starts_with('/') {
        return Err(format!("resource location '{uri}' is not an absolute path"));
    }
    Ok(PathBuf::from(percent_decode(path)?))
}

fn percent_decode(s: &str) -> Result<String, String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = s
                .get(i + 1..i + 3)
                .ok_or_else(|| format!("bad percent-encoding in '{s}'"))?;
            let v =
                u8::from_str_radix(hex, 16).map_err(|_| format!("bad percent-encoding '%{hex}' in '{s}'"))?;
            out.push(v);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("'{s}' does not decode to UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_of_file_uris() {
        let want = PathBuf::from("/tmp/my fmu/resources/");
        for uri in [
            "file:///tmp/my%20fmu/resources/",
            "file:/tmp/my%20fmu/resources/",
            "file://localhost/tmp/my%20fmu/resources/",
        ] {
            assert_eq!(file_uri_to_path(uri).unwrap(), want, "{uri}");
        }
        assert!(file_uri_to_path("http://x/y").is_err());
        assert!(file_uri_to_path("file://server/share").is_err());
        assert!(file_uri_to_path("file:///a%2").is_err());
        assert!(file_uri_to_path("file:relative").is_err());
    }
}
