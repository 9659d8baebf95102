//! Sample chunks: how the span evaluator hands its samples over.
//!
//! A [`SampleChunk`] holds up to [`SAMPLE_CHUNK`] consecutive samples of a span by component
//! (`f`, `gx`, `gy`), as [`SpanEvaluator::eval_chunks`](super::SpanEvaluator::eval_chunks) hands
//! them over; `ChunkSink` fills one and hands it to the consumer when it is full and at the end
//! of the span, and `copy_values` keeps only `f`, in order, for the callers of values. A chunk
//! never holds more than [`SAMPLE_CHUNK`] samples and every access is bounds-checked (nothing
//! here panics).

use super::*;

/// Samples handed over per call by [`SpanEvaluator::eval_chunks`].
pub const SAMPLE_CHUNK: usize = 16;

/// Up to [`SAMPLE_CHUNK`] consecutive samples of a span, stored by component (`f`, `gx`, `gy`
/// arrays), as [`SpanEvaluator::eval_chunks`] hands them over. The forward-differencing fast path
/// fills each component in its own pass over the chunk, so the state of each pass fits a 32-bit
/// core's registers. The gradient arrays hold zeros when gradients are off.
#[derive(Clone, Debug)]
pub struct SampleChunk {
    pub(super) f: [TexValue; SAMPLE_CHUNK],
    pub(super) gx: [i64; SAMPLE_CHUNK],
    pub(super) gy: [i64; SAMPLE_CHUNK],
    /// Samples held, `<= SAMPLE_CHUNK`.
    pub(super) len: usize,
    /// The span's [`SpanInfo::extra_width48`].
    pub(super) extra_width48: i64,
}

impl SampleChunk {
    pub(super) const fn new() -> Self {
        SampleChunk {
            f: [TexValue::ZERO; SAMPLE_CHUNK],
            gx: [0; SAMPLE_CHUNK],
            gy: [0; SAMPLE_CHUNK],
            len: 0,
            extra_width48: 0,
        }
    }

    /// The extra filter width of the chunk's span from octaves culled past the Nyquist limit
    /// ([`SpanInfo::extra_width48`]; the same for every chunk of a span), known before the first
    /// chunk is handed over, so a consumer need not ask [`SpanEvaluator::extra_width48`] first.
    pub const fn extra_width48(&self) -> i64 {
        self.extra_width48
    }

    /// Number of samples.
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the chunk holds no sample.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// `f` of each sample.
    pub fn f(&self) -> &[TexValue] {
        self.f.get(..self.len).unwrap_or(&[])
    }

    /// `gx` of each sample.
    pub fn gx(&self) -> &[i64] {
        self.gx.get(..self.len).unwrap_or(&[])
    }

    /// `gy` of each sample.
    pub fn gy(&self) -> &[i64] {
        self.gy.get(..self.len).unwrap_or(&[])
    }

    /// The samples in order.
    pub fn iter(&self) -> impl Iterator<Item = Sample> + '_ {
        self.f()
            .iter()
            .zip(self.gx())
            .zip(self.gy())
            .map(|((&f, &gx), &gy)| Sample { f, gx, gy })
    }
}

/// A chunk being filled and the consumer it goes to when full (and at the end of the span).
pub(super) struct ChunkSink<'o, 'c> {
    pub(super) chunk: &'o mut SampleChunk,
    pub(super) out: &'o mut (dyn FnMut(&SampleChunk) + 'c),
}

impl ChunkSink<'_, '_> {
    /// Appends one sample.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn push(&mut self, s: Sample) {
        let c = &mut self.chunk;
        let i = c.len;
        if let (Some(f), Some(gx), Some(gy)) = (c.f.get_mut(i), c.gx.get_mut(i), c.gy.get_mut(i)) {
            *f = s.f;
            *gx = s.gx;
            *gy = s.gy;
        }
        self.advance(1);
    }

    /// Free slots before the chunk is handed over (at least 1).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn room(&self) -> usize {
        SAMPLE_CHUNK - self.chunk.len
    }

    /// Marks `k <= room()` more slots as filled, handing the chunk over when it is full.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn advance(&mut self, k: usize) {
        self.chunk.len += k;
        if self.chunk.len >= SAMPLE_CHUNK {
            self.chunk.len = SAMPLE_CHUNK;
            (self.out)(self.chunk);
            self.chunk.len = 0;
        }
    }

    /// Hands over what is left.
    pub(super) fn finish(&mut self) {
        if self.chunk.len > 0 {
            (self.out)(self.chunk);
            self.chunk.len = 0;
        }
    }
}

/// Runs `eval` with a chunk sink that copies each chunk's `f` into `out`, in order.
pub(super) fn copy_values(out: &mut [TexValue], eval: impl FnOnce(&mut ChunkSink<'_, '_>)) {
    let mut chunk = SampleChunk::new();
    let mut at = 0usize;
    let mut copy = |c: &SampleChunk| {
        if let Some(dst) = out.get_mut(at..at + c.len()) {
            // Element by element: `copy_from_slice` keeps a length-mismatch panic.
            for (d, v) in dst.iter_mut().zip(c.f()) {
                *d = *v;
            }
        }
        at += c.len();
    };
    let mut sink = ChunkSink {
        chunk: &mut chunk,
        out: &mut copy,
    };
    eval(&mut sink);
    sink.finish();
}
