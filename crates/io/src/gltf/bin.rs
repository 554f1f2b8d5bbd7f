//! The one binary buffer a written glTF has, with its buffer views and
//! accessors, laid out for streaming ([`Bin::lay_out_for_streaming`]).

use serde_json::{json, Map, Value};

use super::accessor::Component;

/// `bufferView.target` for vertex attributes.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
/// `bufferView.target` for indices.
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// What a buffer view holds, for the order of the data in the buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Section {
    /// Data every level needs: skins, animations, instancing, copied
    /// accessors and primitives the model does not hold.
    #[default]
    Shared,
    /// Images (those the coarsest level of a chain draws, or any).
    Textures,
    /// Images a chain's coarsest level does not draw, with the coarsest
    /// level that does ([`Bin::defer_images`]).
    LevelTextures(usize),
    /// The meshes of one level of detail (0: the input's).
    Level(usize),
}

/// Bytes, views and accessors being written; every view is in buffer 0.
#[derive(Default)]
pub(crate) struct Bin {
    pub data: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
    /// The section of every view, parallel to `views`.
    sections: Vec<Section>,
    /// The section views appended now belong to.
    pub section: Section,
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
        self.sections.push(self.section);
        self.views.len() - 1
    }

    /// The level of detail view `v` holds data of, if any.
    pub(crate) fn level_of(&self, v: usize) -> Option<usize> {
        match self.sections.get(v) {
            Some(&Section::Level(l)) => Some(l),
            _ => None,
        }
    }

    /// Moves image views out of the coarsest level's span into that of
    /// the coarsest level drawing them (`levels`: view and level, from
    /// `image_levels.rs`), so a streaming reader fetches each image once.
    pub(crate) fn defer_images(&mut self, levels: &[(usize, usize)], coarsest: usize) {
        for &(v, level) in levels {
            if let Some(s) = self.sections.get_mut(v) {
                if *s == Section::Textures && level < coarsest {
                    *s = Section::LevelTextures(level);
                }
            }
        }
    }

    /// Moves the views' bytes into the order a streaming reader wants
    /// them: the levels of detail from the coarsest (`coarsest`) to level
    /// 0, each section contiguous and its views in the order they were
    /// written, with the shared data (skins, animations…) and the images
    /// inside the coarsest level's span, after its first view.
    ///
    /// A viewer that loads `MSFT_lod` progressively over HTTP range
    /// requests (Babylon.js) asks for one byte range per level, spanning
    /// everything that level's nodes use: with this order the first range
    /// is the shared data and the coarsest level only, and each finer
    /// level is one more contiguous range after it. The shared data sits
    /// between the coarsest level's views rather than before them because
    /// Babylon issues the first range as soon as the scene's geometry has
    /// asked for its views; an image or animation asking later widens the
    /// range it already fetched and then reads every view at the wrong
    /// offset ("Invalid typed array length", the truck's chain in two
    /// loads of three on a busy machine). Between two views of the
    /// coarsest level, which the first range always holds, a late request
    /// never widens it. With a single level, or a coarsest level of one
    /// view, the shared data comes first.
    ///
    /// An image a finer level is the first to draw ([`Bin::defer_images`])
    /// goes inside that level's span, after its first view, for the same
    /// reason: its range then holds it, and no other range does.
    ///
    /// View indices do not change, only their offsets; each view keeps
    /// its offset modulo 4, so every accessor stays aligned.
    pub(crate) fn lay_out_for_streaming(&mut self, coarsest: usize) {
        let top = Section::Level(coarsest);
        let first_top = (coarsest > 0 && self.sections.iter().filter(|&&s| s == top).count() >= 2)
            .then(|| self.sections.iter().position(|&s| s == top))
            .flatten();
        // The first view of every finer level.
        let mut first = vec![None; coarsest];
        for (v, s) in self.sections.iter().enumerate() {
            if let Section::Level(l) = *s {
                if let Some(f @ None) = first.get_mut(l) {
                    *f = Some(v);
                }
            }
        }
        let sections = &self.sections;
        // (level's place from the coarsest, place within the level).
        let finer = |l: usize| 1 + coarsest.saturating_sub(l);
        let rank = |v: usize| match sections[v] {
            _ if Some(v) == first_top => (0, 0),
            Section::Shared => (0, 1),
            Section::Textures => (0, 2),
            Section::Level(l) if l >= coarsest => (0, 3),
            Section::Level(l) if first[l] == Some(v) => (finer(l), 0),
            Section::LevelTextures(l) => (finer(l), 1),
            Section::Level(l) => (finer(l), 2),
        };
        let mut order: Vec<usize> = (0..self.views.len()).collect();
        // Stable: views of one section keep their order.
        order.sort_by_key(|&v| rank(v));
        let mut data = Vec::with_capacity(self.data.len());
        for v in order {
            let view = &mut self.views[v];
            let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
            let length = view["byteLength"].as_u64().unwrap_or(0) as usize;
            while data.len() % 4 != offset % 4 {
                data.push(0);
            }
            view["byteOffset"] = json!(data.len());
            data.extend_from_slice(self.data.get(offset..offset + length).unwrap_or(&[]));
        }
        self.data = data;
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

    /// The bytes of view `v`.
    fn bytes(b: &Bin, v: usize) -> &[u8] {
        let o = b.views[v]["byteOffset"].as_u64().unwrap() as usize;
        let n = b.views[v]["byteLength"].as_u64().unwrap() as usize;
        &b.data[o..o + n]
    }

    #[test]
    fn streaming_layout_puts_shared_data_and_images_inside_the_coarsest_level_first() {
        // Written as a glTF writer does: level 0, shared, images, level 1,
        // level 2 (a view of 3 bytes and one at residue 2 on the way).
        let mut b = Bin {
            section: Section::Level(0),
            ..Bin::default()
        };
        let l0 = b.view(&[0; 8], None, None);
        b.section = Section::Shared;
        let shared = b.view(&[1; 3], None, None);
        let odd = b.view_from(&[2; 2], 6, Map::new());
        b.section = Section::Textures;
        let image = b.view(&[3; 5], None, None);
        b.section = Section::Level(1);
        let l1 = b.view(&[4; 4], None, None);
        b.section = Section::Level(2);
        let l2a = b.view(&[5; 4], None, None);
        let l2b = b.view(&[6; 4], None, None);
        b.lay_out_for_streaming(2);
        let offset = |v: usize| b.views[v]["byteOffset"].as_u64().unwrap();
        let order = [l2a, shared, odd, image, l2b, l1, l0];
        assert!(order.windows(2).all(|w| offset(w[0]) < offset(w[1])));
        // Packed: each view right after the one before, up to alignment.
        assert_eq!(
            order.map(offset),
            [0, 4, 10, 12, 20, 24, 28],
            "{:?}",
            b.views
        );
        assert_eq!(b.data.len(), 36);
        for (v, byte) in [
            (l0, 0),
            (shared, 1),
            (odd, 2),
            (image, 3),
            (l1, 4),
            (l2a, 5),
            (l2b, 6),
        ] {
            assert!(bytes(&b, v).iter().all(|&x| x == byte), "view {v}");
        }
    }

    #[test]
    fn an_image_a_finer_level_draws_first_goes_inside_that_levels_span() {
        // Level 0 draws image `kept`, level 2 (the coarsest) draws `baked`:
        // the coarsest span holds `baked` only, level 1's nothing extra,
        // level 0's `kept`, after its first view.
        let mut b = Bin {
            section: Section::Level(0),
            ..Bin::default()
        };
        let l0a = b.view(&[0; 4], None, None);
        let l0b = b.view(&[1; 4], None, None);
        b.section = Section::Textures;
        let kept = b.view(&[2; 4], None, None);
        let baked = b.view(&[3; 4], None, None);
        b.section = Section::Level(1);
        let l1 = b.view(&[4; 4], None, None);
        b.section = Section::Level(2);
        let l2a = b.view(&[5; 4], None, None);
        let l2b = b.view(&[6; 4], None, None);
        b.defer_images(&[(kept, 0), (baked, 2)], 2);
        b.lay_out_for_streaming(2);
        let offset = |v: usize| b.views[v]["byteOffset"].as_u64().unwrap();
        let order = [l2a, baked, l2b, l1, l0a, kept, l0b];
        assert_eq!(
            order.map(offset),
            [0, 4, 8, 12, 16, 20, 24],
            "{:?}",
            b.views
        );
        for (v, byte) in [(l0a, 0), (l0b, 1), (kept, 2), (baked, 3), (l1, 4)] {
            assert!(bytes(&b, v).iter().all(|&x| x == byte), "view {v}");
        }
    }

    #[test]
    fn a_single_level_or_a_coarsest_level_of_one_view_puts_shared_data_first() {
        for (coarsest, views) in [(0, 2), (1, 1)] {
            let mut b = Bin {
                section: Section::Level(0),
                ..Bin::default()
            };
            let l0 = b.view(&[0; 4], None, None);
            b.section = Section::Level(coarsest);
            let top: Vec<usize> = (0..views).map(|_| b.view(&[1; 4], None, None)).collect();
            b.section = Section::Shared;
            let shared = b.view(&[2; 4], None, None);
            b.lay_out_for_streaming(coarsest);
            let offset = |v: usize| b.views[v]["byteOffset"].as_u64().unwrap();
            assert_eq!(offset(shared), 0, "coarsest {coarsest}");
            assert!(top.iter().all(|&v| offset(v) > 0));
            assert!(offset(l0) > 0);
        }
    }
}
