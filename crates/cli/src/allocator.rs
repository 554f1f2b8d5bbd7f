//! Allocator settings of the process.
//!
//! A run's big arrays (star lists, quadrics, queues, chunk copies) are
//! freed phase by phase so that the next phase fits in the room they
//! leave. glibc's malloc serves large blocks with `mmap` and returns them
//! to the system when freed, but it raises that threshold each time such a
//! block is freed, up to 32 MiB: later arrays then come from the heap,
//! whose freed pages it keeps. On the dragon (871k triangles) the resident
//! peak stood 40 MB above the live heap's peak. A fixed threshold keeps
//! every block above it mapped and returned when freed; the resident peak
//! then equals the heap's, at no measured cost in time (see
//! docs/benchmarks.md).

/// Blocks from this size up are mapped and returned to the system when
/// freed: well above a collapse's scratch buffers, below every per-vertex
/// or per-face array of a mesh worth simplifying, and below the arrays of
/// the partitioned path's chunks (about 16k faces each: their edges and
/// queues take about 250 KiB, their star lists half that). At 256 KiB
/// those came from the heap, whose pages a chunk's growing star lists
/// fragmented: the dragon's resident peak stood 20 MB above its heap's
/// (229 against 209 MB); at 128 KiB it is the heap's, with no more page
/// faults (224k against 239k) and no measurable time.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 128 * 1024;

/// Applies the settings; call once, first thing in `main`. The one unsafe
/// call of the workspace: a C library setting, no memory is touched.
#[allow(unsafe_code)]
pub fn configure() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only changes malloc's tuning; called before any
    // thread exists. A refusal (return 0) leaves glibc's defaults, which
    // are correct, only hungrier.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
    }
}
