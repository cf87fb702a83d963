//! Parts: the film of a range of sample passes (`foton render --passes A..B`), exactly, so that
//! `foton merge` can sum parts rendered on different machines into the image one render of all
//! their passes gives.
//!
//! A part is an OpenEXR file (ZIP-compressed) that any viewer opens: `R`, `G`, `B` hold the
//! part's own mean (32-bit float). Beside them, the film's state as bit patterns in 32-bit
//! unsigned channels, since EXR has no 64-bit samples: for each f64 of the weighted sums
//! (`sum.R`, `sum.G`, `sum.B`) and the weight sum (`weight`), and for the u64 sample count
//! (`count`), a `.hi` and a `.lo` channel with the upper and lower 32 bits. What the part is
//! goes in text attributes named `foton:part:*` (see [`PartInfo`]).
//!
//! Only the part's window (the `--crop`, or the whole film) is stored, rows from the top.

use std::path::Path;

use exr::meta::attribute::AttributeValue;
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image as ExrImage, Layer, LayerAttributes,
    SmallVec, WritableImage,
};
use glam::DVec3;

use super::output::{temporary_path, text};

/// The part format's version, in `foton:part:format`.
const FORMAT: &str = "1";

/// What a part is: where it came from and everything that must agree for parts to merge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartInfo {
    /// The scene file as given on the command line (for messages; parts match by `scene_hash`).
    pub scene: String,
    /// FNV-1a of the scene file's bytes.
    pub scene_hash: u64,
    /// The sample passes held: `first..end`.
    pub first_pass: u32,
    pub end_pass: u32,
    /// The samples per pixel of the whole render the passes belong to.
    pub render_spp: u32,
    pub seed: u64,
    /// The whole film's size.
    pub width: u32,
    pub height: u32,
    /// The pixels held: `[x0, x1, y0, y1]` (x0 <= x < x1, y0 <= y < y1).
    pub window: [u32; 4],
    /// Every other setting that changes the image, one `name: value` per line, compared as a
    /// whole (the samplers' pattern depends on the render's samples per pixel, so it is here).
    pub settings: String,
    /// Samples the film dropped (non-finite or negative).
    pub rejected: u64,
}

impl PartInfo {
    pub fn window_size(&self) -> (u32, u32) {
        let [x0, x1, y0, y1] = self.window;
        (x1 - x0, y1 - y0)
    }
}

/// A part's film over its window: weighted sums, weight sums and sample counts per pixel.
#[derive(Clone, Debug)]
pub struct Part {
    pub info: PartInfo,
    pub sums: Vec<DVec3>,
    pub weights: Vec<f64>,
    pub counts: Vec<u64>,
}

/// FNV-1a, 64 bits, over `bytes`: names a scene file's content.
pub fn content_hash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}

/// The upper and lower halves of 64-bit words, as two channels.
fn split_channels(
    name: &str,
    words: impl Iterator<Item = u64> + Clone,
) -> [AnyChannel<FlatSamples>; 2] {
    let half = |suffix: &str, shift: u32| {
        AnyChannel::new(
            text(&format!("{name}.{suffix}")),
            FlatSamples::U32(words.clone().map(|w| (w >> shift) as u32).collect()),
        )
    };
    [half("hi", 32), half("lo", 0)]
}

/// Writes `part` to `path` (through a temporary file renamed over it).
pub fn write_part(path: &Path, part: &Part) -> Result<(), String> {
    let info = &part.info;
    let (w, h) = info.window_size();
    if part.sums.len() != w as usize * h as usize {
        return Err(format!(
            "{}: the part's film is not its window's size",
            path.display()
        ));
    }
    let mut attributes = LayerAttributes::named("");
    attributes.software_name = Some(text("foton"));
    let [x0, x1, y0, y1] = info.window;
    for (name, value) in [
        ("format", FORMAT.to_string()),
        ("scene", info.scene.clone()),
        ("scene_hash", format!("{:016x}", info.scene_hash)),
        ("passes", format!("{}..{}", info.first_pass, info.end_pass)),
        ("render_spp", info.render_spp.to_string()),
        ("seed", info.seed.to_string()),
        ("resolution", format!("{}x{}", info.width, info.height)),
        ("window", format!("{x0},{x1},{y0},{y1}")),
        ("settings", info.settings.clone()),
        ("rejected", info.rejected.to_string()),
    ] {
        attributes.other.insert(
            text(&format!("foton:part:{name}")),
            AttributeValue::Text(text(&value)),
        );
    }
    let mean = |c: usize| {
        let values = part
            .sums
            .iter()
            .zip(&part.weights)
            .map(|(s, &wt)| if wt > 0.0 { (s[c] / wt) as f32 } else { 0.0 });
        AnyChannel::new(["R", "G", "B"][c], FlatSamples::F32(values.collect()))
    };
    let mut channels: Vec<AnyChannel<FlatSamples>> = (0..3).map(mean).collect();
    for (c, name) in ["sum.R", "sum.G", "sum.B"].into_iter().enumerate() {
        channels.extend(split_channels(
            name,
            part.sums.iter().map(move |s| s[c].to_bits()),
        ));
    }
    channels.extend(split_channels(
        "weight",
        part.weights.iter().map(|w| w.to_bits()),
    ));
    channels.extend(split_channels("count", part.counts.iter().copied()));
    let layer = Layer::new(
        (w as usize, h as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let temporary = temporary_path(path);
    let written = ExrImage::from_layer(layer)
        .write()
        .to_file(&temporary)
        .map_err(|e| e.to_string())
        .and_then(|()| std::fs::rename(&temporary, path).map_err(|e| e.to_string()))
        .map_err(|e| format!("{}: {e}", path.display()));
    if written.is_err() {
        // Best effort: the temporary may not exist.
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// Reads a part written by [`write_part`]; an error names the file and what is wrong.
pub fn read_part(path: &Path) -> Result<Part, String> {
    let bad = |what: String| format!("{}: not a foton part ({what})", path.display());
    let image = exr::prelude::read_first_flat_layer_from_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let layer = &image.layer_data;
    let attribute = |name: &str| -> Result<String, String> {
        match layer
            .attributes
            .other
            .get(&text(&format!("foton:part:{name}")))
        {
            Some(AttributeValue::Text(t)) => Ok(t.to_string()),
            _ => Err(bad(format!("no foton:part:{name} attribute"))),
        }
    };
    let number = |name: &str| -> Result<u64, String> {
        let value = attribute(name)?;
        value
            .trim()
            .parse()
            .map_err(|_| bad(format!("foton:part:{name} is {value:?}, not a number")))
    };
    if attribute("format")? != FORMAT {
        return Err(bad(format!(
            "format {}, this foton reads {FORMAT}",
            attribute("format")?
        )));
    }
    let pair = |name: &str, separator: &str| -> Result<(u32, u32), String> {
        let value = attribute(name)?;
        value
            .split_once(separator)
            .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
            .ok_or_else(|| bad(format!("foton:part:{name} is {value:?}")))
    };
    let (first_pass, end_pass) = pair("passes", "..")?;
    let (width, height) = pair("resolution", "x")?;
    let window_text = attribute("window")?;
    let window: Vec<u32> = window_text
        .split(',')
        .filter_map(|v| v.trim().parse().ok())
        .collect();
    let window: [u32; 4] = match window[..] {
        [x0, x1, y0, y1] if x0 < x1 && x1 <= width && y0 < y1 && y1 <= height => [x0, x1, y0, y1],
        _ => return Err(bad(format!("foton:part:window is {window_text:?}"))),
    };
    let hash_text = attribute("scene_hash")?;
    let info = PartInfo {
        scene: attribute("scene")?,
        scene_hash: u64::from_str_radix(hash_text.trim(), 16)
            .map_err(|_| bad(format!("foton:part:scene_hash is {hash_text:?}")))?,
        first_pass,
        end_pass,
        render_spp: u32::try_from(number("render_spp")?)
            .map_err(|_| bad("foton:part:render_spp is too large".into()))?,
        seed: number("seed")?,
        width,
        height,
        window,
        settings: attribute("settings")?,
        rejected: number("rejected")?,
    };
    if first_pass >= end_pass || end_pass > info.render_spp {
        return Err(bad(format!(
            "passes {first_pass}..{end_pass} of a {} spp render",
            info.render_spp
        )));
    }
    let (w, h) = info.window_size();
    let n = w as usize * h as usize;
    if (layer.size.x(), layer.size.y()) != (w as usize, h as usize) {
        return Err(bad(format!(
            "{}x{} pixels for a {w}x{h} window",
            layer.size.x(),
            layer.size.y()
        )));
    }
    let words = |name: &str| -> Result<Vec<u64>, String> {
        let half = |suffix: &str| {
            let full = format!("{name}.{suffix}");
            layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name == text(&full))
                .and_then(|c| match &c.sample_data {
                    FlatSamples::U32(v) if v.len() == n => Some(v),
                    _ => None,
                })
                .ok_or_else(|| bad(format!("no 32-bit unsigned channel {full}")))
        };
        let (hi, lo) = (half("hi")?, half("lo")?);
        Ok(hi
            .iter()
            .zip(lo)
            .map(|(&h, &l)| (u64::from(h) << 32) | u64::from(l))
            .collect())
    };
    let floats = |name: &str| -> Result<Vec<f64>, String> {
        Ok(words(name)?.into_iter().map(f64::from_bits).collect())
    };
    let (r, g, b) = (floats("sum.R")?, floats("sum.G")?, floats("sum.B")?);
    Ok(Part {
        info,
        sums: (0..n).map(|i| DVec3::new(r[i], g[i], b[i])).collect(),
        weights: floats("weight")?,
        counts: words("count")?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn part_round_trip_is_exact_and_refuses_other_files() {
        let dir = std::env::temp_dir().join(format!("foton-part-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
        let path = dir.join("a.exr");
        // Values whose lower 32 bits matter, and a count above 2^32.
        let part = Part {
            info: PartInfo {
                scene: "scenes/cornell.lxs".into(),
                scene_hash: content_hash(b"WorldBegin"),
                first_pass: 4,
                end_pass: 9,
                render_spp: 16,
                seed: u64::MAX - 3,
                width: 5,
                height: 4,
                window: [1, 4, 2, 4],
                settings: "max_depth: 8\nsampler: MultiJittered".into(),
                rejected: 17,
            },
            sums: (0..6)
                .map(|i| DVec3::new(0.1 * f64::from(i), 1.0 / 3.0, 1e300))
                .collect(),
            weights: (0..6).map(|i| f64::from(i) / 7.0).collect(),
            counts: (0..6).map(|i| (1 << 33) + i).collect(),
        };
        write_part(&path, &part).unwrap_or_else(|e| panic!("{e}"));
        let read = read_part(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(read.info, part.info);
        assert_eq!(read.sums, part.sums);
        assert_eq!(read.weights, part.weights);
        assert_eq!(read.counts, part.counts);
        // The viewable channels hold the mean.
        let (_, _, rgb) = super::super::read_exr(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(rgb[1].x, (0.1 / (1.0 / 7.0)) as f32);
        // An ordinary image is not a part.
        let plain = dir.join("plain.exr");
        super::super::write_image(
            &plain,
            1,
            1,
            &[glam::Vec3::ONE],
            1.0,
            &super::super::ImageMetadata::default(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let e = read_part(&plain).err().unwrap_or_default();
        assert!(
            e.contains("plain.exr") && e.contains("not a foton part"),
            "{e}"
        );
    }
}
