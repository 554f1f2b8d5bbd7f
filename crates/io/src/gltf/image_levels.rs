//! Which level of detail of a chain first draws each embedded image, so
//! that a streaming viewer fetches every image once, with the coarsest
//! level that needs it ([`super::bin::Bin::lay_out_for_streaming`]).
//!
//! A level's byte range, as a viewer that loads `MSFT_lod` progressively
//! over range requests asks for it (Babylon.js), spans everything the
//! level's meshes use. An image kept from the input for the finer levels
//! but placed with the coarsest level's data was fetched twice: once in
//! the coarsest level's range, where nothing drew it, and again in the
//! range of the first level that did, which then also spanned every image
//! in between (the truck's chain fetched 1.5 MB of its 1.7 MB twice).

use serde_json::Value;

fn index(v: Option<&Value>) -> Option<usize> {
    v.and_then(Value::as_u64).map(|i| i as usize)
}

fn array<'a>(json: &'a Value, key: &str) -> &'a [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// Texture indices a material samples: every texture info, core or
/// extension, is an object under a key ending in `Texture` with an
/// `index`.
fn material_textures(v: &Value, out: &mut Vec<usize>) {
    match v {
        Value::Object(m) => {
            for (key, x) in m {
                if key.ends_with("Texture") {
                    if let Some(t) = index(x.get("index")) {
                        out.push(t);
                    }
                }
                material_textures(x, out);
            }
        }
        Value::Array(a) => a.iter().for_each(|x| material_textures(x, out)),
        _ => {}
    }
}

/// Image indices a texture reads: its `source`, and the `source` of any
/// extension that replaces it (WebP, Basis, AVIF).
fn texture_images(t: &Value, out: &mut Vec<usize>) {
    out.extend(index(t.get("source")));
    if let Some(ext) = t.get("extensions").and_then(Value::as_object) {
        out.extend(ext.values().filter_map(|e| index(e.get("source"))));
    }
}

/// For every image held in a buffer view that some mesh's material
/// samples: (its view, the coarsest level whose meshes sample it), with
/// `accessors` the document's (the written buffer's, not yet in `json`)
/// and `level_of_view` giving the level a mesh's vertex data belongs to
/// (`None` for data of no level).
pub(crate) fn image_view_levels(
    json: &Value,
    accessors: &[Value],
    level_of_view: impl Fn(usize) -> Option<usize>,
) -> Vec<(usize, usize)> {
    let materials = array(json, "materials");
    let (textures, images) = (array(json, "textures"), array(json, "images"));
    let mut coarsest: Vec<Option<usize>> = vec![None; images.len()];
    let (mut tex, mut img) = (Vec::new(), Vec::new());
    for mesh in array(json, "meshes") {
        for prim in array(mesh, "primitives") {
            let level = prim
                .get("attributes")
                .and_then(Value::as_object)
                .and_then(|a| a.values().find_map(|acc| index(Some(acc))))
                .and_then(|acc| index(accessors.get(acc)?.get("bufferView")))
                .and_then(&level_of_view);
            let (Some(level), Some(mat)) = (level, index(prim.get("material"))) else {
                continue;
            };
            tex.clear();
            material_textures(materials.get(mat).unwrap_or(&Value::Null), &mut tex);
            img.clear();
            for &t in &tex {
                texture_images(textures.get(t).unwrap_or(&Value::Null), &mut img);
            }
            for &i in &img {
                if let Some(c) = coarsest.get_mut(i) {
                    *c = Some(c.map_or(level, |c| c.max(level)));
                }
            }
        }
    }
    images
        .iter()
        .zip(coarsest)
        .filter_map(|(image, level)| Some((index(image.get("bufferView"))?, level?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn an_image_belongs_to_the_coarsest_level_that_samples_it() {
        // Views 0 and 1: level 0's and level 2's positions. Image 0 (view
        // 5), the input's texture, is sampled by level 0 alone; image 1
        // (view 6) by level 2's base color; image 2 (view 7), a WebP
        // source, by level 2's emissive texture; image 3 has no view. A
        // primitive with no material samples nothing.
        let accessors = [json!({"bufferView": 0}), json!({"bufferView": 1})];
        let doc = json!({
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
                {"primitives": [{"attributes": {"POSITION": 1}, "material": 1}]},
                {"primitives": [{"attributes": {"POSITION": 1}}]}
            ],
            "materials": [
                {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}},
                 "emissiveTexture": {"index": 2}}
            ],
            "textures": [
                {"source": 0},
                {"source": 1},
                {"extensions": {"EXT_texture_webp": {"source": 2}}},
                {"source": 3}
            ],
            "images": [
                {"bufferView": 5}, {"bufferView": 6}, {"bufferView": 7}, {"uri": "x.png"}
            ]
        });
        let level = |v: usize| match v {
            0 => Some(0),
            1 => Some(2),
            _ => None,
        };
        assert_eq!(
            image_view_levels(&doc, &accessors, level),
            vec![(5, 0), (6, 2), (7, 2)]
        );
    }

    #[test]
    fn an_image_every_level_samples_goes_with_the_coarsest() {
        let accessors = [json!({"bufferView": 0}), json!({"bufferView": 1})];
        let doc = json!({
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
                {"primitives": [{"attributes": {"POSITION": 1}, "material": 0}]}
            ],
            "materials": [{"normalTexture": {"index": 0}}],
            "textures": [{"source": 0}],
            "images": [{"bufferView": 4}]
        });
        let level = |v: usize| Some(v * 3);
        assert_eq!(image_view_levels(&doc, &accessors, level), vec![(4, 3)]);
    }
}
