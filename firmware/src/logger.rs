//! `defmt` global logger over semihosting (QEMU), written to be panic-free.
//!
//! Same wire format as the `defmt-semihosting` crate (rzCOBS-encoded defmt frames written to the
//! semihosting console `:tt` with `SYS_WRITE`), with two differences:
//! - it is panic-free: `defmt-semihosting` panics on re-entrant use, and the `semihosting`
//!   crate's `Stdout` asserts on its file descriptor at every write, either of which would make
//!   the `panic-never` link check fail on the logger instead of on the code under test. Here the
//!   raw `SYS_OPEN`/`SYS_WRITE` calls are used directly and a nested `acquire` (impossible today:
//!   no interrupt handler logs) is counted and its bytes dropped;
//! - a frame is buffered and written with one `SYS_WRITE` (the encoder emits byte by byte),
//!   instead of one host call per byte.
//!
//! Under QEMU the console output goes to the chardev given with
//! `-semihosting-config enable=on,target=native,chardev=ID` (the runner script and
//! `host_sim::device` use a stdio chardev): raw bytes, no translation.
//!
//! With feature `rtt` this module is not built and `defmt-rtt` is the logger instead.
#![allow(unsafe_code)]
// unsafe is needed for: the `unsafe trait defmt::Logger` impl, the raw critical-section
// acquire/release pair that spans `acquire()`..`release()`, the raw semihosting calls, and the
// `Sync` impl of the state cell. Soundness: every access to `STATE` happens between
// `critical_section::acquire()` (in `acquire`) and the matching `release`, on a single core, and
// defmt guarantees it calls `write`/`release` only after `acquire`.

use core::cell::UnsafeCell;
use semihosting::sys::arm_compat::syscall::{syscall_readonly, OperationNumber, ParamRegR};

#[defmt::global_logger]
struct Logger;

/// Bytes buffered before a `SYS_WRITE` (a report frame is well under this).
const BUF: usize = 128;

/// Buffered writer to the semihosting console.
struct Sink {
    /// Semihosting handle of `:tt` opened for writing; -1 if not open (output dropped).
    fd: isize,
    opened: bool,
    buf: [u8; BUF],
    len: usize,
}

struct State {
    /// Nesting depth of `acquire` calls; only depth 1 writes.
    depth: u32,
    restore: critical_section::RestoreState,
    encoder: defmt::Encoder,
    sink: Sink,
}

struct Cell(UnsafeCell<State>);

// SAFETY: see the module comment: accessed only inside the logger's critical section.
unsafe impl Sync for Cell {}

static STATE: Cell = Cell(UnsafeCell::new(State {
    depth: 0,
    restore: critical_section::RestoreState::invalid(),
    encoder: defmt::Encoder::new(),
    sink: Sink {
        fd: -1,
        opened: false,
        buf: [0; BUF],
        len: 0,
    },
}));

/// `SYS_OPEN(":tt", "w")`: the semihosting console for writing (stdout). -1 on failure.
fn open_console() -> isize {
    const NAME: &[u8] = b":tt\0";
    const MODE_W: usize = 4; // ARM semihosting fopen mode index of "w"
    let block = [
        ParamRegR::ptr(NAME.as_ptr()),
        ParamRegR::usize(MODE_W),
        ParamRegR::usize(NAME.len() - 1),
    ];
    // SAFETY: SYS_OPEN reads the 3-word block and the NUL-terminated name, both live here.
    let ret = unsafe { syscall_readonly(OperationNumber::SYS_OPEN, ParamRegR::block(&block)) };
    ret.usize() as isize
}

/// `SYS_WRITE` all of `bytes` to `fd`, giving up silently on any error.
fn write_all(fd: isize, mut bytes: &[u8]) {
    if fd < 0 {
        return;
    }
    while !bytes.is_empty() {
        let block = [
            ParamRegR::isize(fd),
            ParamRegR::buf(bytes),
            ParamRegR::usize(bytes.len()),
        ];
        // SAFETY: SYS_WRITE reads the block and `bytes.len()` bytes of `bytes`.
        let ret = unsafe { syscall_readonly(OperationNumber::SYS_WRITE, ParamRegR::block(&block)) };
        // SYS_WRITE returns the number of bytes *not* written.
        let not_written = ret.usize();
        if not_written == 0 {
            return;
        }
        match bytes.len().checked_sub(not_written) {
            Some(done) if done > 0 => match bytes.get(done..) {
                Some(rest) => bytes = rest,
                None => return,
            },
            _ => return,
        }
    }
}

impl Sink {
    fn push(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if self.len >= BUF {
                self.flush();
            }
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = b;
                self.len += 1;
            }
        }
    }

    fn flush(&mut self) {
        if !self.opened {
            self.opened = true;
            self.fd = open_console();
        }
        if let Some(pending) = self.buf.get(..self.len) {
            write_all(self.fd, pending);
        }
        self.len = 0;
    }
}

// SAFETY: acquire/release bracket a critical section (single core), so frames never interleave.
unsafe impl defmt::Logger for Logger {
    fn acquire() {
        // SAFETY: paired with exactly one `critical_section::release`: in `release()` at depth 1,
        // or right here when nested.
        let restore = unsafe { critical_section::acquire() };
        // SAFETY: inside the critical section.
        let st = unsafe { &mut *STATE.0.get() };
        if st.depth != 0 {
            st.depth = st.depth.wrapping_add(1);
            // SAFETY: releases the nested acquire just made (LIFO); still inside the outer one.
            unsafe { critical_section::release(restore) };
            return;
        }
        st.depth = 1;
        st.restore = restore;
        st.encoder.start_frame(|b| st.sink.push(b));
    }

    unsafe fn flush() {
        // Frames are written out at `release`; semihosting writes are synchronous.
    }

    unsafe fn release() {
        // SAFETY: defmt calls release only after acquire, i.e. inside the critical section.
        let st = unsafe { &mut *STATE.0.get() };
        match st.depth {
            0 => {}
            1 => {
                st.encoder.end_frame(|b| st.sink.push(b));
                st.sink.flush();
                st.depth = 0;
                let restore = st.restore;
                // SAFETY: matches the depth-1 acquire.
                unsafe { critical_section::release(restore) };
            }
            _ => st.depth -= 1,
        }
    }

    unsafe fn write(bytes: &[u8]) {
        // SAFETY: as in release.
        let st = unsafe { &mut *STATE.0.get() };
        if st.depth == 1 {
            st.encoder.write(bytes, |b| st.sink.push(b));
        }
    }
}
