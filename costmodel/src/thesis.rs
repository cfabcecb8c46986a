//! The thesis's own figures, from its own constants: chapter 5.2's stage timings for its
//! test environment on an INMOS T424-20 transputer, and chapter 6.4's depth of the
//! splitter tree, computed by the same model code ([`crate::model::predict_on`],
//! [`crate::model::choose_depth_on`]) that serves `render.sh --depth auto`.
//!
//! Theoharis, *Exploiting Parallelism in the Graphics Pipeline* (1985), 5.2: 1,024
//! four-sided polygons (P_t = 1024, E = 4), half of them clipped out (P_r = 512), a
//! 500×500 screen, depth complexity 1, so W = H = √(500·500·1/512) ≈ 22. The stages'
//! costs in transputer cycles (50 ns each at 20 MHz) are
//!
//! * T_v  = P_t·(138 + E·399)          = 1.8 M cycles, .09 s   (5.2.1)
//! * T_p  = P_r·(138 + E·439)          = 1 M cycles, .05 s     (5.2.2)
//! * T_c  = P_t·(1213 + (E−1)·979)     = 4.2 M cycles, .21 s   (5.2.3, the first clipper,
//!   which reads every polygon)
//! * T_sc = P_r·(1034 + T_cl + (E−2)·(139 + T_IN + T_MH) + 2·T_IN + 2·T_MH
//!   + H·(44 + T_MD + E_aet·(414 + W·152) + T_UP + T_SO)) = 103 M cycles, 5.2 s (5.2.4)
//! * T_SP = P_r·(1430 + (E−1)·1131)    = 2.5 M cycles, .12 s   (6.4, the root splitter)
//!
//! with T_cl = 13686, T_IN = 501, T_MH = 54, T_MD = 71, T_UP = 240, T_SO = 505 and
//! E_aet = 2. In the model's terms ([`Cost`]) these are costs per polygon, per vertex,
//! per scan line of a polygon (a span: P_r·H of them) and per pixel (P_r·W·H), which is
//! exactly how the model of this machine is written; only the constants differ. With a
//! transputer for every process (6.4) and no start-up costs, the model's rule for the
//! depth is the thesis's, and it gives depth 5: 32 leaves.

use crate::look::Environment;
use crate::model::{choose_depth_on, predict_on, Constants, Cost, Machine, Prediction, Target};

/// Seconds a transputer cycle takes on the T424-20 (20 MHz).
pub const CYCLE_S: f64 = 50e-9;

/// The thesis's figures for its environment: (name, formula, cycles, seconds), as 5.2
/// and 6.4 print them.
pub const FIGURES: [(&str, &str, f64, f64); 5] = [
    ("T_v", "P_t·(138 + E·399)", 1.8e6, 0.09),
    ("T_p", "P_r·(138 + E·439)", 1.0e6, 0.05),
    ("T_c", "P_t·(1213 + (E−1)·979)", 4.2e6, 0.21),
    ("T_SP", "P_r·(1430 + (E−1)·1131)", 2.5e6, 0.12),
    (
        "T_sc",
        "P_r·(1034 + T_cl + … + H·(… + E_aet·(414 + W·152) …))",
        103e6,
        5.2,
    ),
];

/// The depth 6.4 chooses: 32-way splitting.
pub const DEPTH: u8 = 5;

/// The environment of 5.2: 1,024 quadrilaterals, 512 in view, 500×500, Dc 1, one frame.
pub fn environment() -> Environment {
    Environment {
        frames: 1,
        polygons: 1024,
        vertices: 4 * 1024,
        relevant: 512,
        relevant_vertices: 4 * 512,
        area: 500.0 * 500.0,
        width: 500,
        height: 500,
        text: false,
    }
}

/// The thesis's constants in seconds on the T424-20, in [`Cost`]'s terms: each formula's
/// per-polygon term less E times the per-vertex one (E = 4 in every formula).
pub fn constants() -> Constants {
    let s = |cycles: f64| cycles * CYCLE_S;
    let (t_cl, t_in, t_mh, t_md, t_up, t_so, e_aet) =
        (13686.0, 501.0, 54.0, 71.0, 240.0, 505.0, 2.0);
    // T_sc per polygon: 1034 + T_cl + 2·T_IN + 2·T_MH, and per edge beyond two
    // 139 + T_IN + T_MH, written as that much a vertex less two of them a polygon; per
    // scan line 44 + T_MD + E_aet·414 + T_UP + T_SO; per pixel E_aet·152 (the AET's two
    // edges each walk the span: the formula's E_aet·W·152 a scan line).
    let edge = 139.0 + t_in + t_mh;
    let hse = Cost {
        polygon: s(1034.0 + t_cl + 2.0 * t_in + 2.0 * t_mh - 2.0 * edge),
        vertex: s(edge),
        span: s(44.0 + t_md + e_aet * 414.0 + t_up + t_so),
        pixel: s(e_aet * 152.0),
        ..Default::default()
    };
    let viewxf = Cost {
        polygon: s(138.0),
        vertex: s(399.0),
        ..Default::default()
    };
    Constants {
        measured_on: "the thesis's INMOS T424-20 (20 MHz), by the Transputer Estimator (5.2)"
            .into(),
        machine: Machine {
            cpu: "INMOS T424-20".into(),
            cores: 0,
            version: "occam, 1985".into(),
            binaries: String::new(),
        },
        // The occam clipper sends on only what is left in view: P_r after it.
        drops_emptied: true,
        // A persp transputer at each leaf (6.3).
        persp_at_leaves: true,
        overheads: Default::default(),
        viewxf_text: viewxf,
        viewxf_binary: viewxf,
        // T_c = P_c·(1213 + (E−1)·979): 234 a polygon and 979 a vertex.
        clip: Cost {
            polygon: s(1213.0 - 979.0),
            vertex: s(979.0),
            ..Default::default()
        },
        // T_SP = P_r·(1430 + (E−1)·1131).
        splitter: Cost {
            polygon: s(1430.0 - 1131.0),
            vertex: s(1131.0),
            ..Default::default()
        },
        // T_p = P_r·(138 + E·439).
        persp: Cost {
            polygon: s(138.0),
            vertex: s(439.0),
            ..Default::default()
        },
        hse,
        // The thesis puts the leaves' pixels back together in video (6.5): no merger.
        merge: Cost::default(),
        resolve: hse,
    }
}

/// The model's figures for the thesis: each stage's seconds (T_v, T_p, T_c, T_SP, T_sc,
/// in [`FIGURES`]' order), the predictions for depths 0–6 with a transputer a process,
/// and the depth chosen.
pub struct Reproduced {
    pub seconds: [f64; 5],
    pub predictions: Vec<Prediction>,
    pub depth: u8,
    pub reason: String,
}

pub fn reproduce() -> Reproduced {
    let k = constants();
    let env = environment();
    let target = Target::unbounded();
    let stage = |p: &Prediction, name: &str| {
        p.stages
            .iter()
            .find(|s| s.stage == name)
            .map_or(0.0, |s| s.each_s)
    };
    let at0 = predict_on(&k, &env, 0, &target);
    let at1 = predict_on(&k, &env, 1, &target);
    let seconds = [
        stage(&at0, "viewxf"),
        stage(&at0, "persp"),
        stage(&at0, "clip"),
        stage(&at1, "splitter"),
        stage(&at0, "hse"),
    ];
    let (depth, reason, predictions) = choose_depth_on(&k, &env, &target, 6);
    Reproduced {
        seconds,
        predictions,
        depth,
        reason,
    }
}

/// `plan thesis` / `chart thesis`: the thesis's figures beside the model's, and the depth.
pub fn report() -> String {
    let r = reproduce();
    let mut t = String::from(
        "Thesis 5.2: stage timings for its environment (1,024 quads, 512 in view, 500x500, Dc 1)\n\
         on the INMOS T424-20 (20 MHz), from its own constants through this model's code\n\n\
         | stage | formula | model cycles | model s | thesis | ratio |\n|---|---|---|---|---|---|\n",
    );
    for ((name, formula, cycles, secs), model) in FIGURES.iter().zip(r.seconds) {
        t += &format!(
            "| {name} | {formula} | {:.2} M | {model:.3} | {:.1} M, {secs} s | {:.3} |\n",
            model / CYCLE_S / 1e6,
            cycles / 1e6,
            model / secs
        );
    }
    t += "\nThesis 6.4: the splitter tree's depth, a transputer a process (HSE leaf against the\n\
          slowest other stage, the pipeline's time the slowest stage's)\n\n\
          | depth | leaves | HSE leaf s | slowest other s | predicted s |\n|---|---|---|---|---|\n";
    for p in &r.predictions {
        let hse = p
            .stages
            .iter()
            .find(|s| s.stage == "hse")
            .map_or(0.0, |s| s.each_s);
        let other = p
            .stages
            .iter()
            .filter(|s| s.stage != "hse")
            .map(|s| s.each_s)
            .fold(0.0, f64::max);
        t += &format!(
            "| {} | {} | {hse:.3} | {other:.3} | {:.3} |\n",
            p.depth,
            1u32 << p.depth,
            p.total_s
        );
    }
    t += &format!(
        "\ndepth {} ({} leaves): {}\nthesis 6.4: \"Our splitter tree should therefore be of depth 5.\"\n",
        r.depth,
        1u32 << r.depth,
        r.reason
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_figure_of_5_2_and_6_4_within_5_percent() {
        let r = reproduce();
        for ((name, _, cycles, secs), model) in FIGURES.iter().zip(r.seconds) {
            // The thesis rounds to two figures (.09 s for 1.78 M cycles): its cycles
            // within 5%, its seconds within 5% or half its last printed digit.
            let c = model / CYCLE_S;
            assert!((c / cycles - 1.0).abs() < 0.05, "{name}: {c} cycles");
            assert!(
                (model / secs - 1.0).abs() < 0.05 || (model - secs).abs() <= 0.005,
                "{name}: {model} s"
            );
        }
        // Exactly: T_v = 1024·(138 + 4·399) cycles, T_c = 1024·4150.
        assert!((r.seconds[0] / CYCLE_S - 1_775_616.0).abs() < 1e-3);
        assert!((r.seconds[2] / CYCLE_S - 4_249_600.0).abs() < 1e-3);
        assert_eq!(r.depth, DEPTH);
        assert!(r.reason.contains("a processor per process"), "{}", r.reason);
    }

    #[test]
    fn the_depth_is_where_the_leaves_drop_below_the_clipper() {
        // 5.2 s of HSE halved per level passes T_c = .21 s between depths 4 and 5.
        let r = reproduce();
        let hse = |d: usize| {
            r.predictions[d]
                .stages
                .iter()
                .find(|s| s.stage == "hse")
                .unwrap()
                .each_s
        };
        assert!(hse(4) > r.seconds[2] && hse(5) < r.seconds[2]);
        assert_eq!(r.predictions[5].bottleneck(), "clip");
        let report = report();
        assert!(report.contains("\ndepth 5 (32 leaves): "), "{report}");
    }
}
