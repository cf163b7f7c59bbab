//! `fmuResourceLocation` URIs: `file:///abs/path`, `file:/abs/path`, `file://localhost/abs/path`,
//! percent-encoded (RFC 3986), with or without a trailing slash. Parsed by the `url` crate; this
//! module only refuses what it would read leniently (a relative path after `file:`, a `%` that
//! starts no escape) instead of guessing.

use std::path::PathBuf;
use url::Url;

/// The folder a `file:` URI names, or a message saying why it is not one.
pub fn file_uri_to_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file:")
        .ok_or_else(|| format!("resource location '{uri}' is not a file: URI"))?;
    if !rest.starts_with('/') {
        return Err(format!("resource location '{uri}' is not an absolute path"));
    }
    if let Some(bad) = bad_escape(uri) {
        return Err(format!(
            "bad percent-encoding '{bad}' in resource location '{uri}'"
        ));
    }
    let url = Url::parse(uri).map_err(|e| format!("resource location '{uri}': {e}"))?;
    // to_file_path refuses hosts other than an empty one or localhost.
    url.to_file_path()
        .map_err(|()| format!("resource location '{uri}' names another host or no local path"))
}

/// The first `%` not followed by two hex digits, with what follows it.
fn bad_escape(s: &str) -> Option<&str> {
    s.match_indices('%').map(|(i, _)| &s[i..]).find(|t| {
        let hex = t.as_bytes().get(1..3);
        !hex.is_some_and(|h| h.iter().all(u8::is_ascii_hexdigit))
    })
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
        assert!(file_uri_to_path("file:///a%zz/b").is_err());
        assert!(file_uri_to_path("file:relative").is_err());
    }

    /// A folder whose name holds spaces, a literal `%` and non-ASCII letters, encoded as Python's
    /// `pathlib.Path.as_uri()` and fmpy write it (RFC 3986 percent-encoding of UTF-8 bytes).
    #[test]
    fn percent_encoded_names_round_trip() {
        let dir = "/tmp/50% done/Überlauf #2/resources";
        let uri = "file:///tmp/50%25%20done/%C3%9Cberlauf%20%232/resources";
        assert_eq!(file_uri_to_path(uri).unwrap(), PathBuf::from(dir));
        // `%25` decodes to a literal `%` once, not again: "%2541" is "%41", not "A".
        assert_eq!(
            file_uri_to_path("file:///a%2541").unwrap(),
            PathBuf::from("/a%41")
        );
    }
}
