//! The batch loops compiled a second time for CPUs with AVX2, picked at run time.
//!
//! The traversal and the packet tests are written with glam's four-lane `Vec4` (SSE2, the
//! x86-64 baseline). SSE2's two-operand instructions overwrite a source, so the compiler
//! copies registers before most operations and, with only 16 vector registers for the ray's
//! splats, the node test and the leaf test, spills them to the stack. The same code compiled
//! with AVX enabled gets VEX's three-operand forms (and memory operands without alignment
//! rules) and BMI's bit instructions for the lane masks: the same operations in the same
//! order on the same values, so the same results bit for bit, in fewer instructions. No FMA:
//! Rust never fuses a product and a sum on its own, so enabling it would change nothing.

/// Runs `body` compiled for AVX2 and BMI2 if the CPU has them, else as compiled for the
/// baseline. `body` must be `#[inline(always)]` so that it is compiled into each version.
#[inline(always)]
pub(crate) fn run<R>(body: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("bmi1")
        && std::arch::is_x86_feature_detected!("bmi2")
    {
        // SAFETY: the CPU has the features `with_avx2` is compiled for.
        return unsafe { with_avx2(body) };
    }
    body()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,bmi2")]
fn with_avx2<R>(body: impl FnOnce() -> R) -> R {
    body()
}

#[cfg(test)]
mod tests {
    use glam::{Affine3A, Vec3};

    use super::super::{Accel, Primitives, SphereInstance};

    /// The batch loop (run through `run`, so compiled for AVX2 where the CPU has it) gives
    /// the same hits, bit for bit, as single queries compiled for the baseline, on a mesh with
    /// spheres and rays from every side.
    #[test]
    fn batch_loop_matches_baseline_queries_bit_for_bit() {
        let point = |i: u32| {
            let h =
                |k: u32| (i.wrapping_mul(2_654_435_761).rotate_left(k) >> 8) as f32 / 16_777_216.0;
            Vec3::new(h(0), h(7), h(13)) * 4.0 - 2.0
        };
        let triangles: Vec<[Vec3; 3]> = (0..500)
            .map(|i| {
                let c = point(i);
                [c, c + 0.3 * point(i + 1000), c + 0.3 * point(i + 2000)]
            })
            .collect();
        let spheres = (0..20)
            .map(|i| SphereInstance {
                object_to_world: Affine3A::from_translation(point(i + 3000)),
                radius: 0.2,
            })
            .collect();
        let accel = Accel::build(&Primitives {
            triangles,
            spheres,
            ..Default::default()
        });
        let origins: Vec<Vec3> = (0..2000).map(|i| point(i + 4000) * 2.0).collect();
        // Aimed into the middle of the scene, where the primitives are densest.
        let dirs: Vec<Vec3> = (0..2000)
            .map(|i| 0.5 * point(i + 5000) - origins[i as usize])
            .collect();
        let t_maxs: Vec<f32> = (0..2000)
            .map(|i| if i % 3 == 0 { 1.5 } else { f32::INFINITY })
            .collect();
        let mut hits = vec![None; 2000];
        let mut occluded = vec![false; 2000];
        accel.closest_hits(&origins, &dirs, 0.0, &t_maxs, &mut hits);
        accel.any_hits(&origins, &dirs, 0.0, &t_maxs, None, &mut occluded);
        let mut found = 0;
        for i in 0..2000 {
            let single = accel.find_closest(origins[i], dirs[i], 0.0, t_maxs[i]);
            assert_eq!(hits[i], single, "ray {i}");
            assert_eq!(
                occluded[i],
                accel.find_any(origins[i], dirs[i], 0.0, t_maxs[i])
            );
            found += single.is_some() as usize;
        }
        assert!(found > 500, "{found} hits");
    }
}
