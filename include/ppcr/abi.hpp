// abi.hpp - the inline namespace that names the Eigen layout ppcr was compiled with.
//
// Eigen aligns its fixed-size vectorisable types (Eigen::Isometry3d, Eigen::Matrix4d, 6x6 and
// 6-vectors of doubles: in the options and results of this API) to EIGEN_MAX_STATIC_ALIGN_BYTES,
// which follows the instruction set the compiler may use: 16 with SSE2 (x86-64's default) or
// NEON, 32 with AVX (for one, -march=haswell), 64 with AVX-512, 0 with static alignment off. A
// program compiled with another value than the library lays the same structs out differently,
// and a call across them reads the wrong bytes: at commit 3c0bad5 a consumer built without
// -march=haswell against a library built with it crashed (docs/RELIABILITY.md, F7).
//
// So every declaration of ppcr lives in an inline namespace named for that value: code that
// names ppcr::X refers to ppcr::eigen_align_16::X in a default x86-64 build, and a program
// compiled with another value asks the linker for ppcr::eigen_align_32::X (say), which the
// library does not define. The mismatch fails at link time, with an undefined reference that
// names the program's side, instead of crashing at run time. Nothing changes in the source: the
// namespace is inline, so ppcr::X and ppcr::detail::X are still spelled so.
//
// Every file that opens namespace ppcr opens this one inside it:
//   namespace ppcr {
//   inline namespace PPCR_ABI_NAMESPACE {
//   ...
//   }  // namespace PPCR_ABI_NAMESPACE
//   }  // namespace ppcr
#pragma once

#include <Eigen/Core>  // defines EIGEN_MAX_STATIC_ALIGN_BYTES

#if EIGEN_MAX_STATIC_ALIGN_BYTES == 0
#define PPCR_ABI_NAMESPACE eigen_align_0
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 8
#define PPCR_ABI_NAMESPACE eigen_align_8
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 16
#define PPCR_ABI_NAMESPACE eigen_align_16
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 32
#define PPCR_ABI_NAMESPACE eigen_align_32
#elif EIGEN_MAX_STATIC_ALIGN_BYTES == 64
#define PPCR_ABI_NAMESPACE eigen_align_64
#else
#error "ppcr/abi.hpp: EIGEN_MAX_STATIC_ALIGN_BYTES is none of 0, 8, 16, 32, 64"
#endif
