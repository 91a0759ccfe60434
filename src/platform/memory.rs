//! How much memory a render may take on this machine: the ceiling of a film
//! and of a scene's meshes.

/// Largest film accepted on any machine, whatever its memory.
pub const MAX_FILM_BYTES: u64 = 32 << 30;

/// The ceiling when the machine's memory cannot be read.
const FALLBACK_FILM_BYTES: u64 = 8 << 30;

/// The largest film accepted here, and why: half the physical memory
/// (`MemTotal` in /proc/meminfo) but at most [`MAX_FILM_BYTES`]; 8 GiB
/// where the memory cannot be read.
pub fn memory_ceiling() -> (u64, &'static str) {
    let total = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|info| mem_total_bytes(&info));
    match total {
        Some(total) if total / 2 < MAX_FILM_BYTES => (total / 2, "half of this machine's memory"),
        Some(_) => (MAX_FILM_BYTES, "the largest film accepted on any machine"),
        None => (FALLBACK_FILM_BYTES, "the machine's memory is unknown"),
    }
}

/// `MemTotal` of /proc/meminfo's text, in bytes.
fn mem_total_bytes(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_is_read_in_bytes() {
        assert_eq!(mem_total_bytes("MemTotal:       1024 kB\n"), Some(1 << 20));
        assert_eq!(mem_total_bytes("nothing"), None);
        let (ceiling, _) = memory_ceiling();
        assert!(ceiling <= MAX_FILM_BYTES);
    }
}
