//! `foton converge SCENE --reference REF.exr`: error against time for several configurations.
//!
//! Each configuration (a label and render options, e.g. `splat: --film splat`) renders the
//! scene at growing sample counts; each render's wall time and relMSE against the reference go
//! to a CSV (configuration, seconds, spp, relmse) and to a log-log chart of relMSE against
//! seconds (SVG, and PNG where a font is found), one curve per configuration. Curves of another renderer (a CSV with the same
//! columns, e.g. from scripts/peers/mitsuba_converge.py) can be drawn beside them.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Parser;
use plotters::prelude::*;

use super::SceneArgs;
use super::compare::compare;
use super::render::prepare;
use crate::film::{Film, read_exr};

/// One configuration's options, parsed as `foton render` would parse them.
#[derive(Parser, Debug)]
#[command(name = "configuration", no_binary_name = true)]
struct ConfigOptions {
    #[command(flatten)]
    scene: SceneArgs,
}

/// One measured point.
#[derive(Clone, Debug)]
pub struct Point {
    pub configuration: String,
    pub seconds: f64,
    pub spp: u32,
    pub rel_mse: f64,
}

pub struct ConvergeArgs<'a> {
    pub scene: &'a Path,
    pub reference: &'a Path,
    /// "label: options"; the options are `foton render`'s.
    pub configurations: &'a [String],
    pub spp: &'a [u32],
    /// CSV files of other renderers' points.
    pub peers: &'a [PathBuf],
    /// The CSV; the chart goes beside it with the extension .svg.
    pub output: &'a Path,
}

pub fn run(args: &ConvergeArgs) -> Result<(), String> {
    let (width, height, reference) = read_exr(args.reference).map_err(|e| format!("error: {e}"))?;
    let configurations: Vec<String> = if args.configurations.is_empty() {
        vec!["default:".into()]
    } else {
        args.configurations.to_vec()
    };
    let mut points = Vec::new();
    for configuration in &configurations {
        let (label, options) = configuration.split_once(':').unwrap_or((configuration, ""));
        let mut words = vec![args.scene.display().to_string()];
        words.extend(options.split_whitespace().map(String::from));
        let parsed = ConfigOptions::try_parse_from(&words)
            .map_err(|e| format!("error: configuration {configuration:?}: {e}"))?;
        for &spp in args.spp {
            let mut scene = parsed.scene.clone();
            scene.spp = Some(spp);
            scene.resolution = Some((width, height));
            let mut renderer = prepare(&scene).map_err(|failure| failure.message)?;
            let stats = renderer.render(|_| true);
            let image = renderer.world.resource::<Film>().mean();
            let point = Point {
                configuration: label.trim().to_string(),
                seconds: stats.elapsed.as_secs_f64(),
                spp: stats.passes,
                rel_mse: compare(&image, &reference).overall.rel_mse,
            };
            println!(
                "{}: {} spp, {:.3} s, relMSE {:.4e}",
                point.configuration, point.spp, point.seconds, point.rel_mse
            );
            points.push(point);
        }
    }
    let mut all = points.clone();
    for peer in args.peers {
        all.extend(read_csv(peer)?);
    }
    write_csv(args.output, &points)?;
    let chart = args.output.with_extension("svg");
    draw_charts(&chart, &all)?;
    println!(
        "{} and {} (and .png) written",
        args.output.display(),
        chart.display()
    );
    Ok(())
}

/// `foton chart`: the chart of points already measured (CSV files, e.g. from
/// scripts/peers/equal_time.py), as `output` (SVG) and beside it as PNG.
pub fn chart(csvs: &[PathBuf], output: &Path) -> Result<(), String> {
    let mut points = Vec::new();
    for csv in csvs {
        points.extend(read_csv(csv)?);
    }
    draw_charts(output, &points)?;
    println!("{} (and .png) written", output.display());
    Ok(())
}

fn write_csv(path: &Path, points: &[Point]) -> Result<(), String> {
    let mut text = String::from("configuration,seconds,spp,relmse\n");
    for p in points {
        let _ = writeln!(
            text,
            "{},{:.6},{},{:.6e}",
            p.configuration, p.seconds, p.spp, p.rel_mse
        );
    }
    std::fs::write(path, text).map_err(|e| format!("error: {}: {e}", path.display()))
}

/// Reads a CSV of points (the header names the columns: configuration, seconds, spp, relmse).
pub fn read_csv(path: &Path) -> Result<Vec<Point>, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("error: {}: {e}", path.display()))?;
    let mut lines = text.lines().enumerate();
    let header: Vec<&str> = lines
        .next()
        .map(|(_, h)| h.split(',').map(str::trim).collect())
        .unwrap_or_default();
    let column = |name: &str| {
        header.iter().position(|h| *h == name).ok_or_else(|| {
            format!(
                "error: {}:1: no column {name:?} in {:?}",
                path.display(),
                header.join(",")
            )
        })
    };
    let [c, s, n, r] = [
        column("configuration")?,
        column("seconds")?,
        column("spp")?,
        column("relmse")?,
    ];
    let mut points = Vec::new();
    for (i, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let bad = || format!("error: {}:{}: cannot read {line:?}", path.display(), i + 1);
        let get = |k: usize| fields.get(k).copied().ok_or_else(bad);
        points.push(Point {
            configuration: get(c)?.to_string(),
            seconds: get(s)?.parse().map_err(|_| bad())?,
            spp: get(n)?.parse().map_err(|_| bad())?,
            rel_mse: get(r)?.parse().map_err(|_| bad())?,
        });
    }
    Ok(points)
}

/// Fonts for the charts' text (plotters measures text with one, for the SVG too).
const FONTS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
];

/// The chart as `path` (SVG) and beside it as PNG; none where no font is found (a warning).
fn draw_charts(path: &Path, points: &[Point]) -> Result<(), String> {
    let error = |e: String| format!("error: {}: {e}", path.display());
    let png = path.with_extension("png");
    let Some(font) = FONTS.iter().find_map(|f| std::fs::read(f).ok()) else {
        eprintln!(
            "warning: no font found ({}): the charts {} and {} are not drawn",
            FONTS.join(", "),
            path.display(),
            png.display()
        );
        return Ok(());
    };
    // The registry keeps fonts for the life of the process: one leaked copy per chart.
    plotters::style::register_font("sans-serif", FontStyle::Normal, font.leak())
        .map_err(|_| error("unreadable font".into()))?;
    draw_chart(
        SVGBackend::new(path, CHART_SIZE).into_drawing_area(),
        points,
    )
    .map_err(error)?;
    let (w, h) = CHART_SIZE;
    let mut pixels = vec![0u8; (w * h * 3) as usize];
    draw_chart(
        BitMapBackend::with_buffer(&mut pixels, CHART_SIZE).into_drawing_area(),
        points,
    )
    .map_err(error)?;
    image::RgbImage::from_raw(w, h, pixels)
        .ok_or_else(|| error("chart buffer size".into()))?
        .save(&png)
        .map_err(|e| format!("error: {}: {e}", png.display()))
}

const CHART_SIZE: (u32, u32) = (800, 560);

/// The log-log chart of relMSE against seconds, one curve per configuration.
fn draw_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    points: &[Point],
) -> Result<(), String> {
    let positive: Vec<&Point> = points
        .iter()
        .filter(|p| p.seconds > 0.0 && p.rel_mse > 0.0)
        .collect();
    let range = |f: fn(&Point) -> f64| {
        let (lo, hi) = positive
            .iter()
            .map(|p| f(p))
            .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
        if lo <= hi {
            lo / 1.5..hi * 1.5
        } else {
            0.1..1.0
        }
    };
    let error = |e: String| e;
    root.fill(&WHITE).map_err(|e| error(e.to_string()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption("relMSE against time", ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            range(|p| p.seconds).log_scale(),
            range(|p| p.rel_mse).log_scale(),
        )
        .map_err(|e| error(e.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("seconds")
        .y_desc("relMSE")
        .x_label_formatter(&|x| format!("{x:.3}"))
        .y_label_formatter(&|y| format!("{y:.1e}"))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| error(e.to_string()))?;
    let mut names: Vec<&str> = Vec::new();
    for p in &positive {
        if !names.contains(&p.configuration.as_str()) {
            names.push(&p.configuration);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let mut curve: Vec<(u32, f64, f64)> = positive
            .iter()
            .filter(|p| p.configuration == *name)
            .map(|p| (p.spp, p.seconds, p.rel_mse))
            .collect();
        // In order of samples: on a busy machine a render can take longer than a bigger one.
        curve.sort_by_key(|p| p.0);
        let curve: Vec<(f64, f64)> = curve.iter().map(|&(_, s, e)| (s, e)).collect();
        chart
            .draw_series(LineSeries::new(curve.clone(), colour.stroke_width(2)))
            .map_err(|e| error(e.to_string()))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        chart
            .draw_series(curve.iter().map(|&p| Circle::new(p, 3, colour.filled())))
            .map_err(|e| error(e.to_string()))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(e.to_string()))?;
    root.present().map_err(|e| error(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trip_and_errors() {
        let dir = std::env::temp_dir().join(format!("foton-converge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("points.csv");
        let points = vec![
            Point {
                configuration: "a".into(),
                seconds: 0.5,
                spp: 4,
                rel_mse: 0.25,
            },
            Point {
                configuration: "a".into(),
                seconds: 1.0,
                spp: 8,
                rel_mse: 0.125,
            },
        ];
        write_csv(&path, &points).unwrap();
        let back = read_csv(&path).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!((back[1].spp, back[1].rel_mse), (8, 0.125));
        draw_charts(&dir.join("chart.svg"), &back).unwrap();
        let svg = std::fs::read_to_string(dir.join("chart.svg")).unwrap();
        assert!(svg.contains("relMSE") && svg.contains("<svg"));
        std::fs::write(&path, "configuration,seconds,spp,relmse\nb,x,1,0.1\n").unwrap();
        let message = read_csv(&path).unwrap_err();
        assert!(message.contains("points.csv:2") && message.contains("b,x,1,0.1"));
    }
}
