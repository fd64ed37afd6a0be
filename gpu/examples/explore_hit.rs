//! Searches behind the worst cases quoted in `tests/hit_properties.rs` and README.md: an
//! exploration program, not a test (it asserts nothing; the claims it found are asserted in
//! `hit_properties.rs`).
//!
//! ```sh
//! cargo run -p rtapprox-gpu --release --example explore_hit -- [box-room|worst|secant-divergence|regime-worst]
//! ```
//!
//! With no argument it runs all four. `MARGIN`, `XR` and `CMIN` environment variables narrow
//! the sampled regime.

use glam::Vec3;
use gpu::distance_map::*;

fn rnd(k: u32) -> f32 {
    gpu::prelude::hash_to_unit(k)
}

fn explore_box_room() {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    let margin: f32 = std::env::var("MARGIN")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0);
    let xr: f32 = std::env::var("XR")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10.0);
    for method in [Method::Secant, Method::FalsePosition] {
        for iters in [0u32, 1, 2, 3, 4, 6, 8, 16, 32] {
            let mut errs = Vec::new();
            let mut shown = Vec::new();
            for k in 0..200000u32 {
                let s = |j: u32| rnd(k * 16 + j);
                let o = lo + margin + (hi - lo - 2.0 * margin) * Vec3::new(s(0), s(1), s(2));
                let xw = lo + (hi - lo) * Vec3::new(s(3), s(4), s(5));
                if (xw - o).length() > xr {
                    continue;
                }
                let r = Vec3::new(s(6) * 2.0 - 1.0, s(7) * 2.0 - 1.0, s(8) * 2.0 - 1.0);
                if r.length() < 0.1 || r.length() > 1.0 {
                    continue;
                }
                let r = r.normalize();
                let room = BoxRoom {
                    min: lo,
                    max: hi,
                    reference: o,
                };
                let exact = room.exact_t(xw, r);
                let h = hit(&room, xw - o, r, method, iters);
                errs.push((h.d - exact).abs());
                let q = xw + r * exact;
                let lprime = o + h.l.normalize() * room.distance(h.l);
                shown.push((lprime - q).length());
            }
            errs.sort_by(f32::total_cmp);
            shown.sort_by(f32::total_cmp);
            let n = errs.len();
            let q = |v: &Vec<f32>, p: f64| v[((n - 1) as f64 * p) as usize];
            println!(
                "{method:?} {iters:2}: |d err| p50 {:.2e} p90 {:.2e} p99 {:.2e} max {:.2e} | shown p50 {:.2e} p99 {:.2e} max {:.2e}",
                q(&errs, 0.5),
                q(&errs, 0.9),
                q(&errs, 0.99),
                errs[n - 1],
                q(&shown, 0.5),
                q(&shown, 0.99),
                shown[n - 1]
            );
        }
    }
}

fn explore_worst() {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    let mut worst = (0.0f32, 0u32);
    for k in 0..20000u32 {
        let s = |j: u32| rnd(k * 16 + j);
        let o = lo + (hi - lo) * Vec3::new(s(0), s(1), s(2));
        let xw = lo + (hi - lo) * Vec3::new(s(3), s(4), s(5));
        let r = Vec3::new(s(6) * 2.0 - 1.0, s(7) * 2.0 - 1.0, s(8) * 2.0 - 1.0);
        if r.length() < 0.1 || r.length() > 1.0 {
            continue;
        }
        let r = r.normalize();
        let room = BoxRoom {
            min: lo,
            max: hi,
            reference: o,
        };
        let exact = room.exact_t(xw, r);
        let h = hit(&room, xw - o, r, Method::FalsePosition, 32);
        let e = (h.d - exact).abs();
        if e > worst.0 {
            worst = (e, k);
        }
    }
    let k = worst.1;
    let s = |j: u32| rnd(k * 16 + j);
    let o = lo + (hi - lo) * Vec3::new(s(0), s(1), s(2));
    let xw = lo + (hi - lo) * Vec3::new(s(3), s(4), s(5));
    let r = Vec3::new(s(6) * 2.0 - 1.0, s(7) * 2.0 - 1.0, s(8) * 2.0 - 1.0).normalize();
    let room = BoxRoom {
        min: lo,
        max: hi,
        reference: o,
    };
    let mut t = Trace::default();
    hit_traced(&room, xw - o, r, Method::FalsePosition, 32, Some(&mut t));
    println!(
        "o {o} x {xw} R {r} exact {} r_len {}",
        room.exact_t(xw, r),
        room.distance(r)
    );
    println!("{t:?}");
}

fn explore_secant_divergence() {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    let mut found = 0;
    for k in 0..200000u32 {
        let s = |j: u32| rnd(k * 16 + j);
        let o = lo + 0.3 + (hi - lo - 0.6) * Vec3::new(s(0), s(1), s(2));
        let xw = lo + (hi - lo) * Vec3::new(s(3), s(4), s(5));
        let r = Vec3::new(s(6) * 2.0 - 1.0, s(7) * 2.0 - 1.0, s(8) * 2.0 - 1.0);
        if r.length() < 0.1 || r.length() > 1.0 {
            continue;
        }
        let r = r.normalize();
        let room = BoxRoom {
            min: lo,
            max: hi,
            reference: o,
        };
        let exact = room.exact_t(xw, r);
        let mut ts = Trace::default();
        hit_traced(&room, xw - o, r, Method::Secant, 8, Some(&mut ts));
        let fp = hit(&room, xw - o, r, Method::FalsePosition, 8);
        if ts.d[8] > exact + 1.0 && (fp.d - exact).abs() < 0.05 {
            found += 1;
            if found < 6 {
                println!(
                    "k {k} o {:?} x {:?} R {:?} exact {exact} fp {} secant d {:?}",
                    o.to_array(),
                    xw.to_array(),
                    r.to_array(),
                    fp.d,
                    ts.d
                );
            }
        }
    }
    println!("found {found}");
}

fn explore_regime_worst() {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    let pick = |u: f32, w: f32| {
        if w < 0.3 {
            0.0
        } else if w < 0.6 {
            1.0
        } else {
            u
        }
    };
    for iters in [4u32, 8, 12, 16, 24, 32] {
        let mut worst = 0.0f32;
        let mut worst_s = 0.0f32;
        for k in 0..400000u32 {
            let s = |j: u32| rnd(k * 16 + j);
            let o = lo
                + 0.3
                + (hi - lo - 0.6)
                    * Vec3::new(pick(s(0), s(9)), pick(s(1), s(10)), pick(s(2), s(11)));
            let dir = Vec3::new(s(3) * 2.0 - 1.0, s(4) * 2.0 - 1.0, s(5) * 2.0 - 1.0);
            if dir.length() < 0.1 || dir.length() > 1.0 {
                continue;
            }
            let off = dir.normalize() * 0.3 * if s(12) < 0.5 { 1.0 } else { s(13).cbrt() };
            let r = Vec3::new(s(6) * 2.0 - 1.0, s(7) * 2.0 - 1.0, s(8) * 2.0 - 1.0);
            if r.length() < 0.1 || r.length() > 1.0 {
                continue;
            }
            let r = r.normalize();
            let room = BoxRoom {
                min: lo,
                max: hi,
                reference: o,
            };
            let exact = room.exact_t(o + off, r);
            let q = o + off + r * exact;
            // cosine between R and the normal of the wall it hits
            let axis = (0..3)
                .min_by(|&a, &b| {
                    let da = (q[a] - lo[a]).abs().min((q[a] - hi[a]).abs());
                    let db = (q[b] - lo[b]).abs().min((q[b] - hi[b]).abs());
                    da.total_cmp(&db)
                })
                .unwrap();
            let cmin: f32 = std::env::var("CMIN")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(0.0);
            if r[axis].abs() < cmin {
                continue;
            }
            let e = (hit(&room, off, r, Method::FalsePosition, iters).d - exact).abs();
            worst = worst.max(e);
            let e = (hit(&room, off, r, Method::Secant, iters.min(8)).d - exact).abs();
            worst_s = worst_s.max(e);
        }
        println!("iters {iters}: FP worst {worst:.3e}  secant(min(it,8)) worst {worst_s:.3e}");
    }
}

fn main() {
    let searches: [(&str, fn()); 4] = [
        ("box-room", explore_box_room),
        ("worst", explore_worst),
        ("secant-divergence", explore_secant_divergence),
        ("regime-worst", explore_regime_worst),
    ];
    let wanted = std::env::args().nth(1);
    let mut ran = false;
    for (name, search) in searches {
        if wanted.as_deref().is_none_or(|w| w == name) {
            println!("== {name}");
            search();
            ran = true;
        }
    }
    if !ran {
        let names: Vec<&str> = searches.iter().map(|(n, _)| *n).collect();
        eprintln!(
            "unknown search {:?}; one of {names:?}",
            wanted.unwrap_or_default()
        );
        std::process::exit(2);
    }
}
