// The vector instruction set the library's few hot kernels run with, chosen
// once per process from the CPU's features: the build itself targets the
// distribution's baseline (x86-64 with SSE2), and kernels compiled for wider
// vectors are picked at run time, as Embree picks its own.
#pragma once

#include <string_view>

namespace isotrace::geometry {

enum class InstructionSet {
    SSE2,    ///< the x86-64 baseline: two doubles a vector
    AVX2,    ///< AVX2 with FMA: four doubles
    AVX512,  ///< AVX-512 F, DQ, BW and VL: eight doubles
};

/// The widest set both the CPU and the process's cap allow. The cap is the
/// environment variable ISOTRACE_MAX_ISA (sse2, avx2 or avx512), read once;
/// it lets one machine run, and test, the narrower paths.
InstructionSet activeInstructionSet();

/// The widest set the CPU supports (the cap aside).
InstructionSet cpuInstructionSet();

/// "sse2", "avx2" or "avx512".
std::string_view instructionSetName(InstructionSet set);

/// The set a name gives; throws std::invalid_argument naming the known ones.
InstructionSet instructionSetNamed(std::string_view name);

/// Of a kernel table compiled once per set, the one the active set runs.
template <class Table>
const Table& tableForActiveSet(const Table& sse2, const Table& avx2, const Table& avx512) {
    switch (activeInstructionSet()) {
    case InstructionSet::AVX512: return avx512;
    case InstructionSet::AVX2: return avx2;
    case InstructionSet::SSE2: break;
    }
    return sse2;
}

}  // namespace isotrace::geometry
