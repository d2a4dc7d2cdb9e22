#pragma once
/// For its scope, the calling thread's floating-point unit treats subnormal operands as zero and gives zero for a
/// result that would be subnormal (x86's DAZ and FTZ modes); leaving the scope restores the mode it found.
///
/// Why the factorisation wants it: a Cholesky factor's fill entries shrink geometrically with their distance from the
/// diagonal, the faster the shorter the step (a matrix M + a K with a small a is nearly diagonal). In single precision
/// many of them fall below 2^-126, and every operation on a subnormal takes a microcode assist of a hundred cycles or
/// more, which on such a matrix (a pressure-formed sheet's first frame, split into steps of a few hundredths of it)
/// would make the refactorisation several times as slow as at a full frame's step. Such entries are zero in the
/// solves' half-precision copy of the factor (whose smallest subnormal is 2^-24) and lie below the rounding of the
/// normal entries they feed, so the preconditioner is the same.
///
/// The mode belongs to a thread, so a kernel run over chunks sets it in every chunk, on whichever thread runs it:
/// every entry is then computed in the same mode, at any thread count and on every SIMD path.

#if defined(__SSE__) || defined(_M_X64)
#include <immintrin.h>
#endif

namespace masse
{
class FlushSubnormals
{
public:
#if defined(__SSE__) || defined(_M_X64)
    FlushSubnormals() : m_saved(_mm_getcsr())
    {
        _mm_setcsr(m_saved | flushToZero | denormalsAreZero);
    }
    ~FlushSubnormals()
    {
        _mm_setcsr(m_saved);
    }
#else
    FlushSubnormals() = default;
#endif
    FlushSubnormals(const FlushSubnormals&) = delete;
    FlushSubnormals& operator=(const FlushSubnormals&) = delete;

private:
#if defined(__SSE__) || defined(_M_X64)
    static constexpr unsigned flushToZero = 0x8000;      // MXCSR.FTZ
    static constexpr unsigned denormalsAreZero = 0x0040; // MXCSR.DAZ
    unsigned m_saved;
#endif
};
} // namespace masse
