#include "geometry/instruction_set.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace isotrace::geometry {

InstructionSet cpuInstructionSet() {
    __builtin_cpu_init();
    // The AVX-512 kernels are compiled for F, DQ, BW and VL together (every
    // AVX-512 CPU since Skylake-SP has the four).
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl"))
        return InstructionSet::AVX512;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return InstructionSet::AVX2;
    return InstructionSet::SSE2;
}

std::string_view instructionSetName(InstructionSet set) {
    switch (set) {
    case InstructionSet::SSE2: return "sse2";
    case InstructionSet::AVX2: return "avx2";
    case InstructionSet::AVX512: return "avx512";
    }
    return "sse2";
}

InstructionSet instructionSetNamed(std::string_view name) {
    for (InstructionSet set : {InstructionSet::SSE2, InstructionSet::AVX2, InstructionSet::AVX512})
        if (name == instructionSetName(set)) return set;
    throw std::invalid_argument("unknown instruction set \"" + std::string(name) + "\" (sse2, avx2 or avx512)");
}

InstructionSet activeInstructionSet() {
    static const InstructionSet active = [] {
        const InstructionSet cpu = cpuInstructionSet();
        const char* cap = std::getenv("ISOTRACE_MAX_ISA");
        if (!cap || !*cap) return cpu;
        InstructionSet capped;
        try {
            capped = instructionSetNamed(cap);
        } catch (const std::invalid_argument&) {
            return cpu;  // the command line reports a bad cap (see checkInstructionSetCap)
        }
        return capped < cpu ? capped : cpu;
    }();
    return active;
}

}  // namespace isotrace::geometry
