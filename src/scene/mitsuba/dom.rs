//! A Mitsuba XML file read by quick-xml into a small element tree that remembers where each element
//! starts, so that every later message can name file, line and column.

use std::path::PathBuf;
use std::sync::Arc;

use quick_xml::XmlVersion;
use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;

use super::error::{MitsubaError, MitsubaWarning, SourceLoc};

/// One XML element: its tag, attributes in file order, child elements, and where it starts.
#[derive(Clone, Debug)]
pub struct Element {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Element>,
    pub loc: SourceLoc,
}

impl Element {
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    pub fn set_attr(&mut self, key: &str, value: String) {
        match self.attrs.iter_mut().find(|(k, _)| k == key) {
            Some((_, v)) => *v = value,
            None => self.attrs.push((key.to_string(), value)),
        }
    }
}

/// Byte offsets of line starts, to turn an offset into a line and a column.
struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    fn new(text: &'a str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self { text, starts }
    }

    /// 1-based line and column (in characters) of a byte offset.
    fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = char_boundary(self.text, offset);
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let column = self.text[start..offset].chars().count() + 1;
        (line + 1, column)
    }

    /// The text of the line holding `offset`, trimmed and cut to a readable length.
    fn line_text(&self, offset: usize) -> String {
        let (line, _) = self.line_col(offset);
        let start = self.starts[line - 1];
        let end = self.starts.get(line).copied().unwrap_or(self.text.len());
        let text = self.text[start..end].trim();
        match text.char_indices().nth(100) {
            Some((cut, _)) => format!("{}…", &text[..cut]),
            None => text.to_string(),
        }
    }
}

/// `offset` moved back to the start of the character it falls in (and to at most the end):
/// quick-xml skips a byte order mark, so its byte positions can fall inside the mark.
fn char_boundary(text: &str, offset: usize) -> usize {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// Parses `text` (the contents of `file`) into its root element. Malformed XML is an error naming
/// file, line and column with the offending line; stray text between elements is a warning.
pub fn parse_document(
    text: &str,
    file: &Arc<PathBuf>,
    warnings: &mut Vec<MitsubaWarning>,
) -> Result<Element, MitsubaError> {
    let lines = LineIndex::new(text);
    let loc_at = |offset: usize| {
        let (line, column) = lines.line_col(offset);
        SourceLoc::new(file, line, column)
    };
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    // Open elements; the document itself is the bottom entry.
    let mut stack: Vec<Element> = Vec::new();
    let mut roots: Vec<Element> = Vec::new();
    loop {
        let before = char_boundary(text, reader.buffer_position() as usize);
        let event = reader.read_event().map_err(|err| {
            let at = reader.error_position() as usize;
            MitsubaError::new(
                &loc_at(at),
                format!("malformed XML: {err}, in `{}`", lines.line_text(at)),
            )
        })?;
        // The event starts at the first non-blank byte after the previous one ended.
        let start = before
            + text[before..]
                .find(|c: char| !c.is_whitespace())
                .unwrap_or(0);
        match event {
            Event::Start(e) => stack.push(element(&e, loc_at(start), &lines, start)?),
            Event::Empty(e) => {
                let el = element(&e, loc_at(start), &lines, start)?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => roots.push(el),
                }
            }
            Event::End(_) => {
                // quick-xml has checked that the names match.
                let el = stack.pop().expect("an end tag closes an open element");
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => roots.push(el),
                }
            }
            Event::Text(t) => {
                let content = t.xml10_content();
                if !content.trim().is_empty() {
                    warnings.push(MitsubaWarning {
                        loc: loc_at(start),
                        message: format!("text `{}` outside any element ignored", content.trim()),
                    });
                }
            }
            Event::CData(_) | Event::GeneralRef(_) => warnings.push(MitsubaWarning {
                loc: loc_at(start),
                message: format!("content `{}` ignored", lines.line_text(start)),
            }),
            Event::Comment(_) | Event::Decl(_) | Event::PI(_) | Event::DocType(_) => {}
            Event::Eof => break,
        }
    }
    if let Some(open) = stack.pop() {
        return Err(MitsubaError::new(
            &open.loc,
            format!("malformed XML: <{}> is never closed", open.name),
        ));
    }
    let mut roots = roots.into_iter();
    let root = roots
        .next()
        .ok_or_else(|| MitsubaError::new(&loc_at(0), "no root element"))?;
    if let Some(extra) = roots.next() {
        return Err(MitsubaError::new(
            &extra.loc,
            format!("malformed XML: a second root element <{}>", extra.name),
        ));
    }
    Ok(root)
}

fn element(
    e: &BytesStart<'_>,
    loc: SourceLoc,
    lines: &LineIndex<'_>,
    start: usize,
) -> Result<Element, MitsubaError> {
    let bad = |what: String| {
        MitsubaError::new(
            &loc,
            format!("malformed XML: {what}, in `{}`", lines.line_text(start)),
        )
    };
    let mut attrs = Vec::new();
    for attr in e.attributes() {
        let attr = attr.map_err(|err| bad(err.to_string()))?;
        let value = attr
            .normalized_value(XmlVersion::Implicit1_0)
            .map_err(|err| bad(err.to_string()))?;
        attrs.push((attr.key.as_ref().to_string(), value.into_owned()));
    }
    Ok(Element {
        name: e.name().as_ref().to_string(),
        attrs,
        children: Vec::new(),
        loc,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Element, MitsubaError> {
        parse_document(text, &Arc::new(PathBuf::from("t.xml")), &mut Vec::new())
    }

    #[test]
    fn elements_remember_line_and_column() {
        let root =
            parse("<scene version=\"3.0.0\">\n  <shape type=\"sphere\"/>\n</scene>").unwrap();
        assert_eq!(root.name, "scene");
        assert_eq!(root.attr("version"), Some("3.0.0"));
        let shape = &root.children[0];
        assert_eq!((shape.loc.line, shape.loc.column), (2, 3));
        assert_eq!(shape.attr("type"), Some("sphere"));
    }

    #[test]
    fn malformed_xml_names_line_column_and_text() {
        let err =
            parse("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>").unwrap_err();
        assert_eq!(err.loc.line, 3, "{err}");
        assert!(err.message.contains("</scene>"), "{err}");
        let err = parse("<scene>\n  <float name=\"a\" value=\"1/>\n</scene>").unwrap_err();
        assert!(err.to_string().starts_with("t.xml:"), "{err}");
        let err = parse("<scene version=\"3.0.0\">").unwrap_err();
        assert!(err.message.contains("never closed"), "{err}");
    }

    #[test]
    fn attribute_values_are_unescaped() {
        let root = parse("<a b=\"x &amp; y\"/>").unwrap();
        assert_eq!(root.attr("b"), Some("x & y"));
    }
}
