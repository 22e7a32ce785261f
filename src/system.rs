//! Stage 0: what the machine gives this process, read from Linux's `/proc` and `/sys`: the
//! memory it may use and what limits it, its resident set, the dense product kernels'
//! per-thread workspace and the physical cores. Elsewhere (not Linux) each reads as unknown
//! (`None`, 0). The memory model that compares a problem's estimate with these is
//! [`crate::pipeline::memory`].

/// What this process may use, in bytes, and what limits it; `None` where nothing can be read
/// (not Linux). The address-space limit counts virtual memory (thread stacks, allocator
/// arenas) too, so 0.5 GB of it is kept for those, or what this process has mapped already
/// and 0.25 GB when that is more (available memory and the cgroup's limit count the memory in
/// use already).
pub fn limit() -> Option<(f64, &'static str)> {
    let mut limits: Vec<(f64, &'static str)> = Vec::new();
    if let Some(kb) = read_field("/proc/meminfo", "MemAvailable:") {
        limits.push((kb * 1024.0, "available memory"));
    }
    if let Ok(text) = std::fs::read_to_string("/sys/fs/cgroup/memory.max") {
        if let Ok(max) = text.trim().parse::<f64>() {
            let used = std::fs::read_to_string("/sys/fs/cgroup/memory.current")
                .ok()
                .and_then(|t| t.trim().parse::<f64>().ok())
                .unwrap_or(0.0);
            limits.push((max - used, "the cgroup's memory limit"));
        }
    }
    if let Ok(text) = std::fs::read_to_string("/proc/self/limits") {
        let soft = text
            .lines()
            .find(|l| l.starts_with("Max address space"))
            .and_then(|l| l.split_whitespace().nth(3))
            .and_then(|v| v.parse::<f64>().ok());
        if let Some(bytes) = soft {
            // At the start the 0.5 GB covers what is mapped; later (after assembly) what is
            // mapped, and 0.25 GB besides.
            let mapped = read_field("/proc/self/status", "VmSize:").unwrap_or(0.0) * 1024.0;
            let kept = (mapped + 0.25e9).max(0.5e9);
            limits.push((bytes - kept, "the address-space limit (ulimit -v)"));
        }
    }
    limits.into_iter().min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The workspace the dense product kernels (faer's x86 matrix product) keep on every thread
/// that multiplies: two buffers the size of the last-level cache as they count it (the L3 of
/// one CPU, divided among the CPUs sharing it, times the CPUs sharing an L1, times the
/// physical cores), allocated on first use without a fallible path, and kept until the thread
/// ends. 64 MiB on 2 cores with a 32 MiB L3; ~1 GB on large machines, where it is what an
/// address-space limit meets first when several threads solve at once. 0 where the cache
/// cannot be read (not Linux).
pub fn kernel_workspace() -> f64 {
    let cache = std::path::Path::new("/sys/devices/system/cpu/cpu0/cache");
    let Ok(entries) = std::fs::read_dir(cache) else { return 0.0 };
    let read = |dir: &std::path::Path, name: &str| {
        std::fs::read_to_string(dir.join(name)).map(|t| t.trim().to_string()).unwrap_or_default()
    };
    let shared = |list: &str| -> f64 {
        list.split(',')
            .map(|item| match item.split_once('-') {
                Some((a, b)) => match (a.parse::<f64>(), b.parse::<f64>()) {
                    (Ok(a), Ok(b)) => b + 1.0 - a,
                    _ => 1.0,
                },
                None => 1.0,
            })
            .sum::<f64>()
            .max(1.0)
    };
    let (mut l3, mut l1_shared) = (0.0, 1.0);
    for dir in entries.flatten().map(|e| e.path()) {
        if !matches!(read(&dir, "type").as_str(), "Data" | "Unified") {
            continue;
        }
        let size = read(&dir, "size");
        let bytes = match size.chars().last() {
            Some('K') => size[..size.len() - 1].parse::<f64>().unwrap_or(0.0) * 1024.0,
            Some('M') => size[..size.len() - 1].parse::<f64>().unwrap_or(0.0) * 1048576.0,
            Some('G') => size[..size.len() - 1].parse::<f64>().unwrap_or(0.0) * 1073741824.0,
            _ => size.parse::<f64>().unwrap_or(0.0),
        };
        let count = shared(&read(&dir, "shared_cpu_list"));
        match read(&dir, "level").as_str() {
            "1" => l1_shared = count,
            "3" => l3 = bytes / count,
            _ => {}
        }
    }
    2.0 * l3 * l1_shared * physical_cores()
}

/// Physical cores: distinct `(physical id, core id)` pairs of /proc/cpuinfo, else the CPUs.
fn physical_cores() -> f64 {
    let text = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let mut cores = std::collections::BTreeSet::new();
    let mut package = String::new();
    for line in text.lines() {
        let Some((key, value)) = line.split_once(':') else { continue };
        match key.trim() {
            "physical id" => package = value.trim().to_string(),
            "core id" => {
                cores.insert((package.clone(), value.trim().to_string()));
            }
            _ => {}
        }
    }
    if cores.is_empty() {
        std::thread::available_parallelism().map_or(1, |n| n.get()) as f64
    } else {
        cores.len() as f64
    }
}

/// The resident set size of this process (`VmRSS`), 0 where it cannot be read.
pub fn resident_bytes() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb * 1024.0)
}

/// The number after `key` in a `key value unit` file such as /proc/meminfo.
fn read_field(path: &str, key: &str) -> Option<f64> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines().find(|l| l.starts_with(key))?.split_whitespace().nth(1)?.parse().ok()
}
