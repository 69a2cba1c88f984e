//! Plots of a sweep's results: `sweep.csv` columns against each other, grouped by the values
//! of other columns (paper Fig. 8: peak roof pressure against tank height, one line per time
//! window; Fig. 10: peak roof force against H'/H, one line per tank width).

use anyhow::{bail, Context, Result};
use slosh_io::{PlotSpec, Series, SeriesStyle, PALETTE};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A plot request `X:Y1,Y2[:G1+G2]`: x column, y columns, optional grouping columns.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPlot {
    /// Column on the horizontal axis.
    pub x: String,
    /// Columns on the vertical axis (one series each, per group).
    pub ys: Vec<String>,
    /// Columns whose values split the rows into groups.
    pub groups: Vec<String>,
}

impl SweepPlot {
    /// Parses `X:Y1,Y2[:G1+G2]`.
    pub fn parse(spec: &str) -> Result<SweepPlot> {
        let parts: Vec<&str> = spec.split(':').collect();
        if parts.len() < 2 || parts.len() > 3 || parts.iter().any(|p| p.trim().is_empty()) {
            bail!(
                "--plot {spec}: expected X:Y or X:Y1,Y2:GROUP (e.g. tank_height:max_roof_p:smoothing_steps)"
            );
        }
        Ok(SweepPlot {
            x: parts[0].trim().to_string(),
            ys: parts[1].split(',').map(|s| s.trim().to_string()).collect(),
            groups: parts
                .get(2)
                .map(|g| g.split('+').map(|s| s.trim().to_string()).collect())
                .unwrap_or_default(),
        })
    }

    /// Checks that every column the plot names is one of `known` (the columns of `sweep.csv`,
    /// see [`crate::sweep::known_columns`]) or a `post_<name>` column of the script's `post`.
    pub fn check_columns(&self, known: &[String]) -> Result<()> {
        let names = std::iter::once(&self.x).chain(&self.ys).chain(&self.groups);
        for name in names {
            // `post_*` and the roof load's scalars (`roof_*`, `p_<sensor>_*`) are known only
            // once a case has run.
            let later =
                name.starts_with("post_") || name.starts_with("roof_") || name.starts_with("p_");
            if !known.contains(name) && !later {
                bail!(
                    "--plot {}: sweep.csv will have no column `{name}`; its columns are: {} \
                     (and post_<name> for each value the script's post(run) returns, and the \
                     roof load's roof_* and p_<sensor>_* columns of a tank with a roof)",
                    self.spec(),
                    known.join(", ")
                );
            }
        }
        Ok(())
    }

    /// The request as written on the command line.
    fn spec(&self) -> String {
        let mut s = format!("{}:{}", self.x, self.ys.join(","));
        if !self.groups.is_empty() {
            s.push(':');
            s.push_str(&self.groups.join("+"));
        }
        s
    }

    /// File stem of the plot in the sweep folder.
    pub fn file_stem(&self) -> String {
        let mut s = format!("plot_{}_vs_{}", self.ys.join("_"), self.x);
        if !self.groups.is_empty() {
            s.push_str("_by_");
            s.push_str(&self.groups.join("_"));
        }
        s
    }
}

/// Axis label of a `sweep.csv` column: its name with the unit of the summary field or of the
/// script parameter it holds (force units say both: N/m for 2D tanks, N for 3D).
pub fn axis_label(column: &str) -> String {
    let unit = match column {
        c if c.starts_with("t_") || c.ends_with("_s") || c == "sim_time" || c == "settle" => "s",
        "max_roof_p" | "kurihara_at_max" | "malhotra_at_max" => "Pa",
        c if c.ends_with("_p") || c.contains("pressure") => "Pa",
        c if c.contains("force") || c.contains("shear") => "N/m in 2D, N in 3D",
        c if c.contains("eta") || c.ends_with("height") || c.contains("width") => "m",
        "depth" | "dx" | "radius" | "amplitude" | "still_level" | "smoothing_length" => "m",
        c if c.contains("ratio") => "–",
        "smoothing_steps" => "steps",
        c if c.contains("omega") => "rad/s",
        _ => "",
    };
    if unit.is_empty() {
        column.to_string()
    } else {
        format!("{column} [{unit}]")
    }
}

/// Draws `plot` from `sweep_csv` into `<dir>/<stem>.png/.svg` and returns the path stem.
/// Rows whose x or y is not a number (failed cases) are left out.
pub fn draw(sweep_csv: &Path, plot: &SweepPlot, title: &str) -> Result<PathBuf> {
    let mut reader = csv::Reader::from_path(sweep_csv)
        .with_context(|| format!("cannot read {}", sweep_csv.display()))?;
    let header: Vec<String> = reader.headers()?.iter().map(|s| s.to_string()).collect();
    let col = |name: &str| -> Result<usize> {
        header.iter().position(|h| h == name).with_context(|| {
            format!(
                "{} has no column {name}; columns: {}",
                sweep_csv.display(),
                header.join(", ")
            )
        })
    };
    let xi = col(&plot.x)?;
    let yis: Vec<usize> = plot.ys.iter().map(|y| col(y)).collect::<Result<_>>()?;
    let gis: Vec<usize> = plot.groups.iter().map(|g| col(g)).collect::<Result<_>>()?;
    // group label → y column → (x, y) points
    let mut data: BTreeMap<String, Vec<Vec<(f64, f64)>>> = BTreeMap::new();
    // group label → (its first group column's value, the other group columns' values)
    let mut group_keys: BTreeMap<String, (String, String)> = BTreeMap::new();
    for record in reader.records() {
        let record = record?;
        let Ok(x) = record[xi].trim().parse::<f64>() else {
            continue;
        };
        let label = gis
            .iter()
            .zip(&plot.groups)
            .map(|(&g, name)| format!("{name}={}", record[g].trim()))
            .collect::<Vec<_>>()
            .join(", ");
        let mut values = gis.iter().map(|&g| record[g].trim().to_string());
        let first = values.next().unwrap_or_default();
        let rest = values.collect::<Vec<_>>().join(",");
        group_keys.entry(label.clone()).or_insert((first, rest));
        let entry = data
            .entry(label)
            .or_insert_with(|| vec![Vec::new(); yis.len()]);
        for (k, &yi) in yis.iter().enumerate() {
            if let Ok(y) = record[yi].trim().parse::<f64>() {
                if x.is_finite() && y.is_finite() {
                    entry[k].push((x, y));
                }
            }
        }
    }
    // (legend, group label, xs, ys)
    let mut owned: Vec<(String, &String, Vec<f64>, Vec<f64>)> = Vec::new();
    for (label, per_y) in &data {
        for (k, points) in per_y.iter().enumerate() {
            let mut points = points.clone();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let name = match (label.is_empty(), plot.ys.len() > 1) {
                (true, _) => plot.ys[k].clone(),
                (false, true) => format!("{} ({label})", plot.ys[k]),
                (false, false) => label.clone(),
            };
            owned.push((
                name,
                label,
                points.iter().map(|p| p.0).collect(),
                points.iter().map(|p| p.1).collect(),
            ));
        }
    }
    // With two or more group columns and one y column, the colour follows the first group
    // column and the line style the others (solid, dashed, points), so that e.g. the widths
    // of Fig. 10 keep their colours across two resolutions.
    let styled = plot.groups.len() >= 2 && plot.ys.len() == 1;
    let order = |values: Vec<&String>| -> Vec<String> {
        let mut seen: Vec<String> = Vec::new();
        for v in values {
            if !seen.contains(v) {
                seen.push(v.clone());
            }
        }
        seen
    };
    let firsts = order(group_keys.values().map(|(f, _)| f).collect());
    let rests = order(group_keys.values().map(|(_, r)| r).collect());
    let series: Vec<Series> = owned
        .iter()
        .map(|(name, label, xs, ys)| {
            let line = Series::line(name.clone(), xs, ys);
            match group_keys.get(*label).filter(|_| styled) {
                Some((first, rest)) => {
                    let colour = firsts.iter().position(|f| f == first).unwrap_or(0);
                    let style = rests.iter().position(|r| r == rest).unwrap_or(0);
                    let (r, g, b) = PALETTE[colour % PALETTE.len()];
                    Series {
                        style: [SeriesStyle::Line, SeriesStyle::Dashed, SeriesStyle::Points]
                            [style % 3],
                        ..line
                    }
                    .with_color(r, g, b)
                }
                None => line,
            }
        })
        .collect();
    let stem = sweep_csv
        .parent()
        .unwrap_or(Path::new("."))
        .join(plot.file_stem());
    slosh_io::line_plot(
        &stem,
        &PlotSpec::new(
            title,
            axis_label(&plot.x),
            plot.ys
                .iter()
                .map(|y| axis_label(y))
                .collect::<Vec<_>>()
                .join(", "),
        ),
        &series,
    )?;
    Ok(stem)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_specs_parse() {
        let p = SweepPlot::parse("tank_height:max_roof_p,kurihara_at_max:smoothing_steps").unwrap();
        assert_eq!(p.x, "tank_height");
        assert_eq!(p.ys, vec!["max_roof_p", "kurihara_at_max"]);
        assert_eq!(p.groups, vec!["smoothing_steps"]);
        assert!(SweepPlot::parse("tank_height").is_err());
        assert_eq!(SweepPlot::parse("a:b:c+d").unwrap().groups, vec!["c", "d"]);
    }

    #[test]
    fn axis_labels_carry_units() {
        assert_eq!(axis_label("tank_height"), "tank_height [m]");
        assert_eq!(axis_label("max_roof_p"), "max_roof_p [Pa]");
        assert_eq!(axis_label("t_max_roof_p"), "t_max_roof_p [s]");
        assert_eq!(axis_label("clearance_ratio"), "clearance_ratio [–]");
        assert_eq!(axis_label("status"), "status");
    }

    #[test]
    fn draws_grouped_lines_from_a_csv() {
        let dir = std::env::temp_dir().join("slosh-sweep-plot-test");
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("sweep.csv");
        std::fs::write(
            &csv,
            "tank_height,smoothing_steps,status,max_roof_p\n0.56,8,completed,900\n0.60,8,completed,700\n0.56,20,completed,800\n0.60,20,failed,\n",
        )
        .unwrap();
        let plot = SweepPlot::parse("tank_height:max_roof_p:smoothing_steps").unwrap();
        let stem = draw(&csv, &plot, "test").unwrap();
        assert!(stem.with_extension("png").exists());
    }

    /// With two group columns the colour follows the first (two widths: two palette colours
    /// for four lines) and the line style the second.
    #[test]
    fn two_group_columns_share_colours_by_the_first() {
        let dir = std::env::temp_dir().join("slosh-sweep-plot-two-groups");
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("sweep.csv");
        std::fs::write(
            &csv,
            "h,width,dx,f\n0.1,0.5,0.02,1\n0.2,0.5,0.02,2\n0.1,0.5,0.01,3\n0.2,0.5,0.01,4\n\
             0.1,1.5,0.02,5\n0.2,1.5,0.02,6\n0.1,1.5,0.01,7\n0.2,1.5,0.01,8\n",
        )
        .unwrap();
        let plot = SweepPlot::parse("h:f:width+dx").unwrap();
        let stem = draw(&csv, &plot, "test").unwrap();
        let svg = std::fs::read_to_string(stem.with_extension("svg"))
            .unwrap()
            .to_uppercase();
        let used: Vec<bool> = PALETTE
            .iter()
            .map(|(r, g, b)| svg.contains(&format!("#{r:02X}{g:02X}{b:02X}")))
            .collect();
        assert_eq!(used.iter().filter(|&&u| u).count(), 2, "{used:?}");
        assert!(used[0] && used[1]);
    }
}
