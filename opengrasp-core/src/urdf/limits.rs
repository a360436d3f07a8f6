//! Resource limits checked on XML text before a parser sees it.
//!
//! urdf-rs (serde), the COLLADA reader and recursive structure walkers use the call stack in
//! proportion to the nesting of a document, so a small hostile file of deeply nested elements
//! could overflow the stack and abort the process. A streaming scan (quick-xml, constant stack)
//! measures size, depth and element count first and rejects excess with
//! [`CoreError::LimitExceeded`].

use crate::error::{CoreError, Result};

/// Limits on an XML document (URDF, SRDF, COLLADA, `package.xml`), checked by a streaming scan
/// before parsing.
///
/// The defaults are far above any real robot description (MoveIt's PR2 URDF is 138 KB, 10
/// levels deep, 2,700 elements) and far below what exhausts a thread's stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct XmlLimits {
    /// Largest document accepted, in bytes. Default: 64 MiB.
    pub max_bytes: usize,
    /// Deepest element nesting accepted (the root element is depth 1). Default: 64.
    pub max_depth: usize,
    /// Most elements accepted. Default: 2,000,000.
    pub max_elements: usize,
}

impl Default for XmlLimits {
    fn default() -> Self {
        Self { max_bytes: 64 << 20, max_depth: 64, max_elements: 2_000_000 }
    }
}

/// Scans `bytes` as XML and checks `limits`.
///
/// # Errors
/// [`CoreError::LimitExceeded`] naming `document`; `malformed(reason)` if the scan meets
/// invalid XML (the scan stops there, so nothing unchecked reaches the parser).
pub(crate) fn check_xml(
    bytes: &[u8],
    limits: &XmlLimits,
    document: &'static str,
    malformed: impl Fn(String) -> CoreError,
) -> Result<()> {
    let exceeded = |what, limit, actual| CoreError::LimitExceeded { document, what, limit, actual };
    if bytes.len() > limits.max_bytes {
        return Err(exceeded("size in bytes", limits.max_bytes, bytes.len()));
    }
    let mut reader = quick_xml::Reader::from_reader(bytes);
    let mut buf = Vec::new();
    let (mut depth, mut elements) = (0usize, 0usize);
    loop {
        let event = reader.read_event_into(&mut buf).map_err(|e| malformed(format!("xml: {e}")))?;
        match event {
            quick_xml::events::Event::Start(_) => {
                depth += 1;
                elements += 1;
                if depth > limits.max_depth {
                    return Err(exceeded("nesting depth", limits.max_depth, depth));
                }
            }
            quick_xml::events::Event::Empty(_) => {
                elements += 1;
                if depth + 1 > limits.max_depth {
                    return Err(exceeded("nesting depth", limits.max_depth, depth + 1));
                }
            }
            quick_xml::events::Event::End(_) => depth = depth.saturating_sub(1),
            quick_xml::events::Event::Eof => return Ok(()),
            _ => {}
        }
        if elements > limits.max_elements {
            return Err(exceeded("element count", limits.max_elements, elements));
        }
        buf.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str, limits: &XmlLimits) -> Result<()> {
        check_xml(text.as_bytes(), limits, "urdf", |reason| CoreError::MalformedUrdf { reason })
    }

    #[test]
    fn depth_size_and_count() {
        let limits = XmlLimits { max_bytes: 1000, max_depth: 3, max_elements: 5 };
        assert!(check("<a><b><c/></b></a>", &limits).is_ok());
        assert!(matches!(
            check("<a><b><c><d/></c></b></a>", &limits),
            Err(CoreError::LimitExceeded { what: "nesting depth", limit: 3, actual: 4, .. })
        ));
        assert!(matches!(
            check("<a><b/><b/><b/><b/><b/></a>", &limits),
            Err(CoreError::LimitExceeded { what: "element count", limit: 5, actual: 6, .. })
        ));
        let big = format!("<a>{}</a>", " ".repeat(1000));
        assert!(matches!(check(&big, &limits), Err(CoreError::LimitExceeded { what: "size in bytes", .. })));
        assert!(matches!(check("<a><b></a>", &limits), Err(CoreError::MalformedUrdf { .. })));
    }
}
