//! A bounded YAML reader: YAML text to a [`serde_json::Value`], event by event.
//!
//! MoveIt writes planning scenes and requests as plain YAML (block and flow collections,
//! plain and quoted scalars, no anchors). This reader drives `yaml-rust2`'s event parser
//! itself rather than its recursive loader, so that hostile input cannot exhaust the stack or
//! memory: aliases are rejected (no "billion laughs" expansion), nesting is limited to
//! [`MAX_DEPTH`] levels and a document to [`MAX_NODES`] nodes. Plain scalars are typed as YAML
//! 1.2's core schema does (null, booleans, integers, floats including `.inf` / `.nan`);
//! quoted scalars stay strings.

use serde_json::{Map, Number, Value};
use yaml_rust2::parser::{Event, Parser};
use yaml_rust2::scanner::TScalarStyle;

/// Deepest nesting of collections accepted (MoveIt documents nest about 8 levels).
pub const MAX_DEPTH: usize = 64;
/// Most nodes (scalars and collections) accepted in one document.
pub const MAX_NODES: usize = 4_000_000;

/// Why a YAML text was rejected: a message with the position.
pub type YamlError = String;

enum Frame {
    Seq(Vec<Value>),
    Map(Map<String, Value>, Option<String>),
}

/// Parses the first document of `text`.
///
/// # Errors
/// A message for a syntax error, an alias, a non-scalar mapping key, nesting deeper than
/// [`MAX_DEPTH`] or more than [`MAX_NODES`] nodes.
pub fn parse(text: &str) -> Result<Value, YamlError> {
    let mut parser = Parser::new_from_str(text);
    let mut stack: Vec<Frame> = Vec::new();
    let mut nodes = 0usize;
    let mut root: Option<Value> = None;
    loop {
        let (event, mark) = parser.next_token().map_err(|e| e.to_string())?;
        let at = || format!("line {} column {}", mark.line(), mark.col() + 1);
        let value = match event {
            Event::StreamEnd => break,
            Event::Nothing | Event::StreamStart | Event::DocumentStart => continue,
            Event::DocumentEnd => {
                if root.is_some() {
                    break;
                }
                continue;
            }
            Event::Alias(_) => return Err(format!("aliases are not supported ({})", at())),
            Event::SequenceStart(..) | Event::MappingStart(..) => {
                if stack.len() >= MAX_DEPTH {
                    return Err(format!("nesting deeper than {MAX_DEPTH} levels ({})", at()));
                }
                nodes += 1;
                if nodes > MAX_NODES {
                    return Err(format!("more than {MAX_NODES} nodes"));
                }
                stack.push(if matches!(event, Event::SequenceStart(..)) {
                    Frame::Seq(Vec::new())
                } else {
                    Frame::Map(Map::new(), None)
                });
                continue;
            }
            Event::SequenceEnd | Event::MappingEnd => match stack.pop() {
                Some(Frame::Seq(items)) => Value::Array(items),
                Some(Frame::Map(map, None)) => Value::Object(map),
                _ => return Err(format!("unbalanced collection ({})", at())),
            },
            Event::Scalar(text, style, _, _) => {
                nodes += 1;
                if nodes > MAX_NODES {
                    return Err(format!("more than {MAX_NODES} nodes"));
                }
                if style == TScalarStyle::Plain {
                    plain_scalar(&text)
                } else {
                    Value::String(text)
                }
            }
        };
        match stack.last_mut() {
            None => {
                root = Some(value);
            }
            Some(Frame::Seq(items)) => items.push(value),
            Some(Frame::Map(map, key)) => match key.take() {
                Some(k) => {
                    map.insert(k, value);
                }
                None => match value {
                    Value::String(s) => *key = Some(s),
                    Value::Number(n) => *key = Some(n.to_string()),
                    Value::Bool(b) => *key = Some(b.to_string()),
                    Value::Null => *key = Some(String::new()),
                    _ => return Err(format!("mapping keys must be scalars ({})", at())),
                },
            },
        }
    }
    Ok(root.unwrap_or(Value::Null))
}

/// Types a plain scalar by YAML 1.2's core schema.
fn plain_scalar(text: &str) -> Value {
    match text {
        "" | "~" | "null" | "Null" | "NULL" => return Value::Null,
        "true" | "True" | "TRUE" => return Value::Bool(true),
        "false" | "False" | "FALSE" => return Value::Bool(false),
        _ => {}
    }
    // JSON has no infinities or NaN: `.inf` / `.nan` stay strings, which the number readers of
    // the callers reject as not a (finite) number.
    let first = text.as_bytes()[0];
    if first.is_ascii_digit() || first == b'-' || first == b'+' || first == b'.' {
        if let Ok(i) = text.parse::<i64>() {
            return Value::Number(i.into());
        }
        if let Ok(f) = text.parse::<f64>() {
            if let Some(n) = Number::from_f64(f) {
                return Value::Number(n);
            }
        }
    }
    Value::String(text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_and_flow_collections_become_json() {
        let v = parse("a: [1, 2.5, -3e-2]\nb:\n  - {x: true, y: ~}\n  - 'quoted 1'\nc: text\n").unwrap();
        assert_eq!(v["a"][1].as_f64(), Some(2.5));
        assert_eq!(v["a"][2].as_f64(), Some(-0.03));
        assert_eq!(v["b"][0]["x"], Value::Bool(true));
        assert_eq!(v["b"][0]["y"], Value::Null);
        assert_eq!(v["b"][1], Value::String("quoted 1".into()));
        assert_eq!(v["c"], Value::String("text".into()));
    }

    #[test]
    fn aliases_and_deep_nesting_are_rejected() {
        assert!(parse("a: &x [1]\nb: *x\n").unwrap_err().contains("aliases"));
        let deep = "[".repeat(200) + &"]".repeat(200);
        assert!(parse(&deep).is_err());
    }
}
