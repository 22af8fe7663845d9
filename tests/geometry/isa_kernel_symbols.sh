#!/usr/bin/env bash
# The objects of the vector kernels (geometry/CMakeLists.txt,
# isotrace_isa_kernels) define their code in namespaces of their own,
# isotrace::geometry::<set>:: and isotrace_eigen_<set>::. Any other global or
# weak symbol they define (an inline function of a shared header, a template
# the other files instantiate too) has one name and several definitions,
# and the linker may keep the kernel's copy for every caller: it must then
# hold no VEX- or EVEX-encoded instruction (AVX and wider), or a binary run
# on an older CPU could die in code it never meant to use.
set -euo pipefail
checked=0
failed=0
# CTest hands the object list over as one argument, separated by ';'.
objects=()
for argument in "$@"; do IFS=';' read -r -a parts <<< "$argument"; objects+=("${parts[@]}"); done
for object in "${objects[@]}"; do
  case "$object" in
    *_sse2.cpp.o) isa=sse2 ;;
    *_avx2.cpp.o) isa=avx2 ;;
    *_avx512.cpp.o) isa=avx512 ;;
    *) echo "isa_kernel_symbols: $object: not a kernel object" >&2; exit 2 ;;
  esac
  disassembly=$(objdump -d --no-show-raw-insn "$object")
  # Defined symbols whose type letter is upper case (global) or weak.
  while read -r type mangled; do
    name=$(c++filt <<< "$mangled")
    case "$name" in
      "isotrace::geometry::$isa::"*|*"isotrace_eigen_$isa::"*) continue ;;
      # std::experimental::simd's helpers for this set's machine flags (a
      # template argument encodes them): only files compiled with the same
      # flags can define that name.
      *"_MachineFlagsTemplate<"*) continue ;;
    esac
    [[ "$type" =~ ^[TtWw]$ ]] || continue  # data: the same bytes wherever it is defined
    # The function's body: from its label to the next blank line.
    body=$(awk -v label="<$mangled>:" '$0 ~ label { on = 1; next } on && /^$/ { exit } on' <<< "$disassembly")
    if grep -Eq $'\t''v[a-z]|%[yz]mm|%k[0-7]' <<< "$body"; then
      echo "isa_kernel_symbols: $(basename "$object") defines $type $name with AVX instructions" >&2
      failed=1
    fi
  done < <(nm --defined-only "$object" | awk '$2 ~ /^[A-Z]$/ || $2 ~ /^[uvw]$/ { print $2, $3 }')
  checked=$((checked + 1))
done
if ((checked == 0)); then echo "isa_kernel_symbols: no objects given" >&2; exit 2; fi
if ((failed)); then exit 1; fi
echo "isa_kernel_symbols: $checked objects share no AVX code under other names"
