//! The one binary buffer a written glTF has, with its buffer views and
//! accessors.

use serde_json::{json, Map, Value};

use super::accessor::Component;

/// `bufferView.target` for vertex attributes.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
/// `bufferView.target` for indices.
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Bytes, views and accessors being written; every view is in buffer 0.
#[derive(Default)]
pub(crate) struct Bin {
    pub data: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
}

impl Bin {
    /// Pads the data so that the next byte starts at `residue` modulo 4.
    fn align(&mut self, residue: usize) {
        while self.data.len() % 4 != residue % 4 {
            self.data.push(0);
        }
    }

    /// Appends a view holding `bytes`, 4-byte aligned; returns its index.
    pub(crate) fn view(
        &mut self,
        bytes: &[u8],
        stride: Option<usize>,
        target: Option<u32>,
    ) -> usize {
        let mut v = Map::new();
        if let Some(s) = stride {
            v.insert("byteStride".into(), json!(s));
        }
        if let Some(t) = target {
            v.insert("target".into(), json!(t));
        }
        self.view_from(bytes, 0, v)
    }

    /// Appends a view holding `bytes` with the other properties of
    /// `template` (name, stride, target, extras…). The view starts at the
    /// same offset modulo 4 as `old_offset`, so accessors whose alignment
    /// relied on it stay aligned.
    pub(crate) fn view_from(
        &mut self,
        bytes: &[u8],
        old_offset: u64,
        mut template: Map<String, Value>,
    ) -> usize {
        self.align((old_offset % 4) as usize);
        template.insert("buffer".into(), json!(0));
        template.insert("byteOffset".into(), json!(self.data.len()));
        template.insert("byteLength".into(), json!(bytes.len()));
        self.data.extend_from_slice(bytes);
        self.views.push(Value::Object(template));
        self.views.len() - 1
    }

    /// Appends an accessor over a whole view; returns its index.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accessor(
        &mut self,
        view: usize,
        component: Component,
        normalized: bool,
        count: usize,
        type_name: &str,
        bounds: Option<(Vec<f64>, Vec<f64>)>,
    ) -> usize {
        let mut a = Map::new();
        a.insert("bufferView".into(), json!(view));
        a.insert("componentType".into(), json!(component.gl()));
        if normalized {
            a.insert("normalized".into(), json!(true));
        }
        a.insert("count".into(), json!(count));
        a.insert("type".into(), json!(type_name));
        if let Some((lo, hi)) = bounds {
            a.insert("min".into(), json!(lo));
            a.insert("max".into(), json!(hi));
        }
        self.accessors.push(Value::Object(a));
        self.accessors.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_are_aligned_and_copied_views_keep_their_residue() {
        let mut b = Bin::default();
        b.view(&[1, 2, 3], None, None);
        let v = b.view(&[4; 8], Some(4), Some(ARRAY_BUFFER));
        assert_eq!(b.views[v]["byteOffset"], 4);
        assert_eq!(b.views[v]["byteStride"], 4);
        let c = b.view_from(&[9; 2], 6, Map::new());
        assert_eq!(b.views[c]["byteOffset"].as_u64().unwrap() % 4, 2);
        assert_eq!(b.views[c]["byteLength"], 2);
    }
}
