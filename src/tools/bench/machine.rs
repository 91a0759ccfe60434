//! What a bench ran on: the processor, the threads and the widest vector
//! extension the processor has.
//!
//! A ratio to a vectorised peer depends on the last: Mitsuba's LLVM backend
//! compiles its wavefront for the widest lanes it finds (8 f32 lanes with
//! AVX2, 16 with AVX-512), while lumiere's path loop is scalar, so the same
//! build measures about twice the per-sample gap on an AVX-512 processor
//! (`docs/benchmarks.md`). The summary names the machine for that reason.

/// One line: processor model, worker threads of the current pool, widest vectors.
pub fn describe() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| model_name(&text))
        .unwrap_or_else(|| "unknown processor".into());
    format!(
        "{model}, {} threads, widest vectors {}",
        rayon::current_num_threads(),
        widest_vectors()
    )
}

/// The first `model name` of a `/proc/cpuinfo` text.
pub fn model_name(cpuinfo: &str) -> Option<String> {
    cpuinfo.lines().find_map(|line| {
        let (key, value) = line.split_once(':')?;
        (key.trim() == "model name" && !value.trim().is_empty()).then(|| value.trim().to_string())
    })
}

/// The widest vector extension this processor runs, with its f32 lanes.
pub fn widest_vectors() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            "AVX-512 (16 f32 lanes)"
        } else if std::arch::is_x86_feature_detected!("avx2") {
            "AVX2 (8 f32 lanes)"
        } else if std::arch::is_x86_feature_detected!("avx") {
            "AVX (8 f32 lanes)"
        } else {
            "SSE2 (4 f32 lanes)"
        }
    }
    #[cfg(target_arch = "aarch64")]
    {
        "NEON (4 f32 lanes)"
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    {
        "unknown"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_is_the_first_model_name_line() {
        let cpuinfo = "processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel\t\t: 17\n\
                       model name\t: AMD EPYC 9B14\nflags\t\t: fpu avx2\n\n\
                       processor\t: 1\nmodel name\t: something else\n";
        assert_eq!(model_name(cpuinfo).as_deref(), Some("AMD EPYC 9B14"));
        assert_eq!(model_name("processor\t: 0\nmodel\t\t: 17\n"), None);
        assert_eq!(model_name("model name\t:   \n"), None);
    }
}
