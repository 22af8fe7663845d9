#!/usr/bin/env bash
# The objects of the vector kernels (geometry/CMakeLists.txt,
# isotrace_isa_kernels) may define, as global or weak symbols, only names in
# their own namespaces, isotrace::geometry::<set>:: and isotrace_eigen_<set>::. Anything else (an inline
# function of a shared header, a template both they and the baseline files
# instantiate) would be one name with two definitions, and the linker could
# keep the AVX-512 one for every caller, to die on an AVX2 machine.
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
  # Defined symbols whose type letter is upper case (global) or a weak one.
  while read -r type name; do
    case "$name" in
      "isotrace::geometry::$isa::"*) ;;
      # Eigen compiled under a name of the set's own (dense_solver_kernels.cpp).
      "isotrace_eigen_$isa::"*|*" isotrace_eigen_$isa::"*) ;;
      # The exception personality's address, the same in every object.
      DW.ref.__gxx_personality_v0) ;;
      *) echo "isa_kernel_symbols: $(basename "$object") defines $type $name" >&2; failed=1 ;;
    esac
  done < <(nm -C --defined-only "$object" | awk '$2 ~ /^[A-Z]$/ || $2 ~ /^[uvw]$/ { $1 = ""; sub(/^ /, ""); t = $1; $1 = ""; sub(/^ /, ""); print t, $0 }')
  checked=$((checked + 1))
done
if ((checked == 0)); then echo "isa_kernel_symbols: no objects given" >&2; exit 2; fi
if ((failed)); then exit 1; fi
echo "isa_kernel_symbols: $checked objects define only their own namespace's symbols"
