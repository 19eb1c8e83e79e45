// abi.hpp - the inline namespace that names the Eigen alignment ppcr was compiled with.
//
// Eigen aligns its fixed-size vectorisable types (Eigen::Isometry3d, Eigen::Matrix4d, 6x6
// matrices and 6-vectors of doubles: in the options and results of this API) to
// EIGEN_MAX_STATIC_ALIGN_BYTES, and its heap allocations to EIGEN_DEFAULT_ALIGN_BYTES. Both follow
// the compiler's flags: with Eigen 3.4 on x86-64, 16 by default, 32 with AVX (for one, -mavx or
// -march=haswell), 64 with AVX-512; 0 when set so (EIGEN_MAX_STATIC_ALIGN_BYTES=0,
// EIGEN_DONT_ALIGN, EIGEN_DONT_VECTORIZE) or on targets Eigen does not vectorise for. A program
// compiled with other values than the library lays the same structs out differently, and a call
// across them reads the wrong bytes: a consumer compiled with -mavx against a default build
// aborted (docs/RELIABILITY.md, F7).
//
// So every declaration of ppcr lives in an inline namespace named for both values: code that
// names ppcr::X refers to ppcr::eigen_align16_heap16::X in a default x86-64 build, and a program
// compiled with -mavx asks the linker for ppcr::eigen_align32_heap32::X, which that library does
// not define. The mismatch fails at link time, with an undefined reference that names the
// program's side, as soon as the program calls a function of ppcr that is not inline. Nothing
// changes in the source (the namespace is inline: ppcr::X and ppcr::detail::X are spelled so),
// except that code outside ppcr must not forward-declare ppcr's types (namespace ppcr { struct X; }
// would declare another X): include the header instead.
//
// Every file that opens namespace ppcr opens this one inside it:
//   namespace ppcr {
//   inline namespace PPCR_ABI_NAMESPACE {
//   ...
//   }  // namespace PPCR_ABI_NAMESPACE
//   }  // namespace ppcr
#pragma once

#include <Eigen/Core>  // defines EIGEN_MAX_STATIC_ALIGN_BYTES and EIGEN_DEFAULT_ALIGN_BYTES

// The two values as plain numbers (Eigen defines them through other macros), for pasting.
#if EIGEN_MAX_STATIC_ALIGN_BYTES == 0
#define PPCR_ABI_STATIC_ALIGN 0
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 8
#define PPCR_ABI_STATIC_ALIGN 8
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 16
#define PPCR_ABI_STATIC_ALIGN 16
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 32
#define PPCR_ABI_STATIC_ALIGN 32
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 64
#define PPCR_ABI_STATIC_ALIGN 64
#else
#error "ppcr/abi.hpp: EIGEN_MAX_STATIC_ALIGN_BYTES is none of 0, 8, 16, 32, 64"
#endif
#if EIGEN_DEFAULT_ALIGN_BYTES == 0
#define PPCR_ABI_HEAP_ALIGN 0
#elif EIGEN_DEFAULT_ALIGN_BYTES == 8
#define PPCR_ABI_HEAP_ALIGN 8
#elif EIGEN_DEFAULT_ALIGN_BYTES == 16
#define PPCR_ABI_HEAP_ALIGN 16
#elif EIGEN_DEFAULT_ALIGN_BYTES == 32
#define PPCR_ABI_HEAP_ALIGN 32
#elif EIGEN_DEFAULT_ALIGN_BYTES == 64
#define PPCR_ABI_HEAP_ALIGN 64
#else
#error "ppcr/abi.hpp: EIGEN_DEFAULT_ALIGN_BYTES is none of 0, 8, 16, 32, 64"
#endif

// A program built against the library through CMake (find_package or add_subdirectory) is told the
// alignment the library was compiled with (PPCR_LIBRARY_STATIC_ALIGN and PPCR_LIBRARY_HEAP_ALIGN,
// CMakeLists.txt): a mismatch stops its compilation here rather than its link.
#if defined(PPCR_LIBRARY_STATIC_ALIGN) && defined(PPCR_LIBRARY_HEAP_ALIGN) && \
    (PPCR_LIBRARY_STATIC_ALIGN != PPCR_ABI_STATIC_ALIGN ||                    \
     PPCR_LIBRARY_HEAP_ALIGN != PPCR_ABI_HEAP_ALIGN)
#error \
    "ppcr: this code is compiled with other instruction-set flags (-march, -mavx, EIGEN_ macros) than the ppcr library it uses, so Eigen would lay out ppcr's types differently: build ppcr and this code with the same flags (third_party/README.md)"
#endif

#define PPCR_ABI_PASTE(s, h) eigen_align##s##_heap##h
#define PPCR_ABI_NAME(s, h) PPCR_ABI_PASTE(s, h)
/// eigen_align<EIGEN_MAX_STATIC_ALIGN_BYTES>_heap<EIGEN_DEFAULT_ALIGN_BYTES>
#define PPCR_ABI_NAMESPACE PPCR_ABI_NAME(PPCR_ABI_STATIC_ALIGN, PPCR_ABI_HEAP_ALIGN)
