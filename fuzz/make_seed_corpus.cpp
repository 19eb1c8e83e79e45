// make_seed_corpus.cpp - writes a seed corpus of small VALID files of every variant the readers
// accept, one folder per fuzz target: <out>/ply, <out>/pcd, <out>/xyz, <out>/transform, and small
// registration problems for fuzz_registration: <out>/registration.
// Usage: ppcr_fuzz_make_seeds <output folder>. Generated at build time, never committed.
#include <lzf.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "fuzz_registration_input.hpp"
#include "ppcr/io.hpp"

namespace {

template <typename T>
void put(std::string* out, T value, bool big_endian = false) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out->push_back(static_cast<char>(bytes[big_endian ? sizeof(T) - 1 - i : i]));
  }
}

// IHDR 4 x 3, 16-bit gray; IDAT (zlib) of depths 1000 + 300 i, 0 at i = 5; IEND.
constexpr char kDepthPng[] =
    "\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x00\x04\x00\x00\x00\x03\x10\x00\x00\x00\x00"
    "\xc1\x0f\x2d\x59\x00\x00\x00\x23IDAT\x78\xda\x63\x60\x7e\xc1\x2a\xc2\xe6\xc0\x9e\xc3\xc0\x31"
    "\x83\x81\x81\xeb\x03\x8f\x0c\x03\xaf\x07\x5f\x09\xff\x02\x81\x33\x00\x47\x0f\x05\xe2\x13"
    "\x2a\xdd\xaf\x00\x00\x00\x00IEND\xae\x42\x60\x82";

bool save(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(f);
}

std::string ply_seed(const char* encoding, bool big_endian, bool faces_first) {
  std::string f = std::string("ply\nformat ") + encoding + " 1.0\ncomment seed\nobj_info seed\n";
  const std::string faces = "element face 1\nproperty list uchar int vertex_indices\n";
  if (faces_first) f += faces;
  f += "element vertex 3\nproperty float x\nproperty uchar red\nproperty double y\n"
       "property list ushort short extra\nproperty int z\n";
  if (!faces_first) f += faces;
  f += "end_header\n";
  const bool ascii = std::strcmp(encoding, "ascii") == 0;
  auto face = [&] {
    if (ascii) {
      f += "3 0 1 2\n";
    } else {
      put<std::uint8_t>(&f, 3, big_endian);
      for (int i = 0; i < 3; ++i) put<std::int32_t>(&f, i, big_endian);
    }
  };
  if (faces_first) face();
  for (int v = 0; v < 3; ++v) {
    if (ascii) {
      f += std::to_string(0.5 * v) + " 200 " + std::to_string(-1.25 * v) + " 2 7 8 " +
           std::to_string(v) + "\n";
    } else {
      put<float>(&f, 0.5f * static_cast<float>(v), big_endian);
      put<std::uint8_t>(&f, 200, big_endian);
      put<double>(&f, -1.25 * v, big_endian);
      put<std::uint16_t>(&f, 2, big_endian);
      put<std::int16_t>(&f, 7, big_endian);
      put<std::int16_t>(&f, 8, big_endian);
      put<std::int32_t>(&f, v, big_endian);
    }
  }
  if (!faces_first) face();
  return f;
}

// A UTF-8 byte-order mark, which every reader skips at the start of a file.
const std::string kBom = "\xEF\xBB\xBF";

const char kPcdHead[] =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal _ rgb\n"
    "SIZE 4 8 2 4 1 4\nTYPE F F I F U U\nCOUNT 1 1 1 3 2 1\nWIDTH 2\nHEIGHT 2\n"
    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\n";

void pcd_point(std::string* f, int i) {
  put<float>(f, i == 2 ? std::numeric_limits<float>::quiet_NaN() : 0.5f * static_cast<float>(i));
  put<double>(f, -0.25 * i);
  put<std::int16_t>(f, static_cast<std::int16_t>(i));
  for (int k = 0; k < 3; ++k) put<float>(f, 1.0f);
  f->append("\0\0", 2);
  put<std::uint32_t>(f, 0xff00ffu);
}

std::string pcd_compressed() {
  // structure of arrays, without the "_" padding field (as PCL writes it)
  std::string soa;
  for (int i = 0; i < 4; ++i) put<float>(&soa, 0.5f * static_cast<float>(i));
  for (int i = 0; i < 4; ++i) put<double>(&soa, -0.25 * i);
  for (int i = 0; i < 4; ++i) put<std::int16_t>(&soa, static_cast<std::int16_t>(i));
  for (int i = 0; i < 12; ++i) put<float>(&soa, 1.0f);
  for (int i = 0; i < 4; ++i) put<std::uint32_t>(&soa, 0xff00ffu);
  std::string packed(soa.size() * 2 + 16, '\0');
  const unsigned int n = lzf_compress(soa.data(), static_cast<unsigned int>(soa.size()), &packed[0],
                                      static_cast<unsigned int>(packed.size()));
  packed.resize(n);
  std::string f = std::string(kPcdHead) + "DATA binary_compressed\n";
  put<std::uint32_t>(&f, n);
  put<std::uint32_t>(&f, static_cast<std::uint32_t>(soa.size()));
  return f + packed;
}

// ---- fuzz_registration seeds (layout: fuzz_registration_input.hpp)

struct RegistrationSeed {
  std::string header = std::string(ppcr_fuzz::kHeaderSize, '\0');  // all 0: library defaults
  std::string points;
  void set(int at, int value) { header[static_cast<std::size_t>(at)] = static_cast<char>(value); }
  void cloud(int at, int unit, int offset, int count) {
    set(at, unit);
    set(at + 1, offset);
    set(at + 2, count);
  }
  void point(double x, double y, double z) {  // in cloud units (i16 / 1024)
    for (double v : {x, y, z}) put<std::int16_t>(&points, static_cast<std::int16_t>(v * 1024.0));
  }
  void raw_point(std::int16_t x, std::int16_t y, std::int16_t z) {
    for (std::int16_t v : {x, y, z}) put<std::int16_t>(&points, v);
  }
  std::string bytes() const { return header + points; }
};

// Deterministic pseudo-random numbers in [-1, 1) (no <random>: the bytes must not depend on the
// standard library).
struct Lcg {
  std::uint64_t state;
  double next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 4503599627370496.0 - 1.0;
  }
};

// A box corner scene: three faces of a 2-unit cube (well constrained), `count` points.
void box_points(RegistrationSeed* s, int count, std::uint64_t seed, double jitter) {
  Lcg g{seed};
  for (int i = 0; i < count; ++i) {
    const double a = g.next(), b = g.next(), n = jitter * g.next();
    switch (i % 3) {
      case 0:
        s->point(a, b, -1.0 + n);
        break;
      case 1:
        s->point(-1.0 + n, a, b);
        break;
      default:
        s->point(a, -1.0 + n, b);
    }
  }
}

bool registration_seeds(const std::filesystem::path& dir) {
  namespace f = ppcr_fuzz;
  bool ok = true;
  int index = 0;
  auto save_seed = [&](const char* name, const RegistrationSeed& s) {
    ok &= save(dir / (std::to_string(index++) + "_" + name + ".bin"), s.bytes());
  };
  {  // defaults, target = source moved by a small pose
    RegistrationSeed s;
    s.set(f::kFlags0, 64);
    s.cloud(f::kSourceCode, 0, 0, 48);
    s.cloud(f::kTargetCode, 0, 0, 0);
    const int pose[6] = {3, -2, 4, 5, -3, 2};
    for (int i = 0; i < 6; ++i) s.set(f::kTruePose + i, pose[i]);
    box_points(&s, 48, 1, 0.0);
    save_seed("box_defaults", s);
    s.set(f::kFlags0, 64 | 1);  // plane model
    save_seed("box_plane", s);
    s.set(f::kFlags1, 4);  // the boundary rule flipped
    save_seed("box_plane_boundary_flipped", s);
    s.set(f::kFlags1, 0);
    s.set(f::kFlags0, 64 | 2 | 8 | 16);  // Gaussian, fixed scale 0.25, two threads
    s.set(f::kScale, -2);
    save_seed("box_gaussian_fixed", s);
    s.set(f::kFlags0, 64 | 4);  // raw scale
    s.set(f::kScale, 0);
    save_seed("box_raw", s);
  }
  {  // independent samples of the box in source and target, an initial guess, k = 1
    RegistrationSeed s;
    s.set(f::kMaxNeighbours, 248);  // k = 32 << (248 - 240) % 6 = 128
    s.cloud(f::kSourceCode, 0, 0, 40);
    s.cloud(f::kTargetCode, 0, 0, 60);
    const int pose[6] = {1, 0, -1, 2, 2, -2};
    for (int i = 0; i < 6; ++i) s.set(f::kInitialPose + i, pose[i]);
    box_points(&s, 40, 2, 0.01);
    box_points(&s, 60, 3, 0.01);
    save_seed("box_independent_k128", s);
  }
  {  // a plane (z = 0), both models; a line; all points identical
    RegistrationSeed s;
    s.set(f::kFlags0, 64 | 1);
    s.cloud(f::kSourceCode, 0, 0, 40);
    s.cloud(f::kTargetCode, 0, 0, 0);
    s.set(f::kTruePose + 3, 4);
    Lcg g{4};
    for (int i = 0; i < 40; ++i) s.point(g.next(), g.next(), 0.0);
    save_seed("plane_plane_model", s);
    s.set(f::kFlags0, 64);
    save_seed("plane_point_model", s);
    RegistrationSeed line = s;
    line.points.clear();
    for (int i = 0; i < 40; ++i) line.point(g.next(), 0.0, 0.0);
    save_seed("line", line);
    RegistrationSeed same = s;
    same.points.clear();
    for (int i = 0; i < 40; ++i) same.point(0.5, 0.25, -0.125);
    save_seed("identical_points", same);
  }
  {  // georeferenced: both clouds 1e6 units away (independent target with the same offset)
    RegistrationSeed s;
    s.cloud(f::kSourceCode, 0, 1, 40);
    s.cloud(f::kTargetCode, 0, 1, 40);
    box_points(&s, 40, 5, 0.0);
    box_points(&s, 40, 5, 0.0);
    save_seed("far_1e6", s);
    s.cloud(f::kTargetCode, 0, 0, 40);  // only the source far away: no correspondence
    save_seed("far_source_only", s);
  }
  {  // millimetres: unit 2^10, radius 2^10, raw and EM
    RegistrationSeed s;
    s.set(f::kFlags0, 64);
    s.set(f::kRadius, 10);
    s.cloud(f::kSourceCode, 30, 0, 48);
    s.cloud(f::kTargetCode, 30, 0, 0);
    s.set(f::kTruePose, 3);
    box_points(&s, 48, 6, 0.0);
    save_seed("box_mm_em", s);
    s.set(f::kFlags0, 64 | 4);
    save_seed("box_mm_raw", s);
  }
  {  // non-finite and huge coordinates mixed in
    RegistrationSeed s;
    s.set(f::kFlags0, 64);
    s.cloud(f::kSourceCode, 0, 0, 24);
    s.cloud(f::kTargetCode, 0, 0, 4);
    box_points(&s, 16, 7, 0.0);
    for (std::int16_t code = -32768; code <= -32761; ++code) s.raw_point(code, 0, 1024);
    for (std::int16_t code = -32768; code <= -32765; ++code) s.raw_point(0, code, 0);
    save_seed("non_finite_mixed", s);
  }
  {  // extreme parameters: tiny and huge radius and dof, many neighbours, voxel filters
    RegistrationSeed s;
    s.set(f::kFlags0, 64);
    s.cloud(f::kSourceCode, 0, 0, 32);
    s.cloud(f::kTargetCode, 0, 0, 0);
    box_points(&s, 32, 8, 0.0);
    s.set(f::kRadius, -128);
    s.set(f::kRadius + 1, 0);  // 1e-300
    save_seed("radius_1e-300", s);
    s.set(f::kRadius + 1, 1);  // 1e300
    save_seed("radius_1e300", s);
    s.set(f::kRadius, 0);
    s.set(f::kRadius + 1, 0);
    s.set(f::kDof, -128);  // dof 5e-300, then 5e300
    save_seed("dof_tiny", s);
    s.set(f::kDof + 1, 1);
    save_seed("dof_huge", s);
    s.set(f::kDof, 0);
    s.set(f::kDof + 1, 0);
    s.set(f::kMaxNeighbours, 245);  // 1024
    s.set(f::kFlags1, 16 | 32);     // voxel leaves 2^-3
    s.set(f::kSourceVoxel, -3);
    s.set(f::kTargetVoxel, -3);
    save_seed("k1024_voxel", s);
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out = argv[1];
  for (const char* sub : {"ply", "pcd", "xyz", "transform", "registration"}) {
    std::filesystem::create_directories(out / sub);
  }
  bool ok = true;
  // PLY: every encoding, faces before/after, list property in the vertex element; our writer.
  ok &= save(out / "ply" / "ascii.ply", ply_seed("ascii", false, true));
  ok &= save(out / "ply" / "le.ply", ply_seed("binary_little_endian", false, false));
  ok &= save(out / "ply" / "be.ply", ply_seed("binary_big_endian", true, true));
  std::string crlf =
      "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\n"
      "property float y\r\nproperty float z\r\nend_header\r\n1 2 3\r\nnan 0 0\r\n";
  ok &= save(out / "ply" / "crlf.ply", crlf);
  const ppcr::PointCloud cloud = {Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(-1, 2e10, 3)};
  ok &= ppcr::io::write_cloud((out / "ply" / "written.ply").string(), cloud).ok();
  ok &= save(out / "ply" / "bom.ply", kBom + crlf);  // a UTF-8 byte-order mark before "ply"
  // PCD: ascii, binary, binary_compressed, organized with NaN, an old v.5 header; our writer.
  std::string ascii = std::string(kPcdHead) + "DATA ascii\n";
  ascii +=
      "0 0 0 1 1 1 0 0 16711935\n0.5 -0.25 1 1 1 1 0 0 16711935\n"
      "nan nan nan 1 1 1 0 0 0\n1.5 -0.75 3 1 1 1 0 0 16711935\n";
  ok &= save(out / "pcd" / "ascii.pcd", ascii);
  std::string binary = std::string(kPcdHead) + "DATA binary\n";
  for (int i = 0; i < 4; ++i) pcd_point(&binary, i);
  ok &= save(out / "pcd" / "binary.pcd", binary);
  ok &= save(out / "pcd" / "compressed.pcd", pcd_compressed());
  ok &= save(out / "pcd" / "v5.pcd",
             "VERSION .5\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 2\n"
             "DATA ascii\n1 2 3\n4 5 6\n");
  ok &= ppcr::io::write_cloud((out / "pcd" / "written.pcd").string(), cloud).ok();
  // As PCL's command-line tools write them: the data section padded with zeros; and with a BOM.
  ok &= save(out / "pcd" / "padded_binary.pcd", binary + std::string(100, '\0'));
  ok &= save(out / "pcd" / "padded_compressed.pcd", pcd_compressed() + std::string(100, '\0'));
  ok &= save(out / "pcd" / "bom_ascii.pcd", kBom + ascii);
  // XYZ: blanks, CSV with header, comments, PTS count; our writer.
  ok &= save(out / "xyz" / "plain.xyz", "1 2 3\n4\t5 6\n\n# c\n7 8 9 # t\r\n");
  ok &= save(out / "xyz" / "header.csv", "x,y,z,i\n1.5,2,3,4\n-1e-3,+2,nan,0\n");
  ok &= save(out / "xyz" / "scan.pts", "2\n1 2 3 4 5 6 7\n8 9 10 11 12 13 14\n");
  ok &= ppcr::io::write_cloud((out / "xyz" / "written.xyz").string(), cloud).ok();
  // Columns chosen by a header row's names; a BOM; CloudCompare's "//X" header.
  ok &= save(out / "xyz" / "normals_first.csv", "nx,ny,nz,x,y,z\n0,0,1,1.5,2,3\n0,1,0,4,5,6\n");
  ok &= save(out / "xyz" / "bom_zyx.csv", kBom + std::string("Z, Y, X\n3,2,1\n6,5,4\n"));
  ok &= save(out / "xyz" / "cloudcompare.txt", "//X Y Z R G B\n1 2 3 255 0 0\n4 5 6 0 255 0\n");
  ok &= save(out / "xyz" / "bom.pts", kBom + std::string("1\n1 2 3\n"));
  // A 4 x 3 depth image (16-bit grayscale PNG, one hole), for fuzz_xyz's content detection.
  ok &= save(out / "xyz" / "depth.png", std::string(kDepthPng, sizeof kDepthPng - 1));
  // Transforms: 16 numbers, 12 numbers with comments.
  ok &= save(out / "transform" / "t16.txt", "1 0 0 1.5\n0 1 0 -2\n0 0 1 0.25\n0 0 0 1\n");
  ok &= save(out / "transform" / "t12.txt", "# gt\n0.6 -0.8 0 1\n0.8 0.6 0 2 # row\n0 0 1 3\n");
  ok &= save(out / "transform" / "bom.txt", kBom + std::string("1 0 0 0\n0 1 0 0\n0 0 1 0\n"));
  // Registration: small valid problems of each kind (see registration_seeds()).
  ok &= registration_seeds(out / "registration");
  if (!ok) {
    std::fprintf(stderr, "could not write the seed corpus under %s\n", out.string().c_str());
    return 1;
  }
  return 0;
}
