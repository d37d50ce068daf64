#include "geometry/mesh_io.h"

#include "core/data_dirs.h"
#include "core/diagnostics.h"
#include "core/files.h"
#include "core/limits.h"
#include "core/units.h"
#include "geometry/texture.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/IOStream.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <fstream>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <functional>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>

#include <fmt/format.h>

namespace sscs {

namespace {

/// assimp reads coordinates in single precision: 1.2 in a file arrives as 1.2000000477, which
/// would make a pallet 48 nm longer than written and a clearance of exactly its minimum fail.
/// A float holds about 7 significant digits, so rounding to 7 gives back the decimal the file
/// wrote (and changes nothing a float could tell apart).
double as_written(float x) {
  if (!std::isfinite(x) || x == 0) return x;
  char text[32];
  auto [end, ec] = std::to_chars(text, text + sizeof text, static_cast<double>(x), std::chars_format::scientific, 6);
  double value = x;
  if (ec == std::errc()) std::from_chars(text, end, value);
  return value;
}

/// "" when a mesh of `n` triangles is within SSCS_MAX_MESH_TRIANGLES, else why not.
std::string too_many_triangles(uintmax_t n) {
  const double max_triangles = limit("SSCS_MAX_MESH_TRIANGLES", kMaxMeshTriangles);
  if (static_cast<double>(n) <= max_triangles) return "";
  return fmt::format("it has {} triangles, above the limit of {:.0f} (raise it with SSCS_MAX_MESH_TRIANGLES, or simplify "
                     "the mesh)", n, max_triangles);
}

/// Why a mesh file must not reach assimp: too large (it would take many times its size in
/// memory), or a binary glTF whose header does not match the file (assimp reads a corrupt 22-byte
/// .glb into gigabytes). "" when it may be read.
std::string unfit_mesh_file(const std::string& path) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  const uintmax_t max_bytes = limit_bytes("SSCS_MAX_MESH_MB", kMaxMeshFileMb);
  if (!ec && size > max_bytes)
    return fmt::format("it is {:.0f} MB, above the {:.0f} MB limit of a mesh file (raise it with SSCS_MAX_MESH_MB)",
                       size / 1e6, max_bytes / 1e6);
  if (!ec && size == 0) return "the file is empty";
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".stl" && !ec) {
    // A binary STL says how many triangles it holds (84 + 50 bytes each): refused before reading.
    // A file that is neither that nor ASCII ("solid" first) is named as such, as assimp tells
    // the two apart.
    std::ifstream in(path, std::ios::binary);
    unsigned char h[84] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    const uint32_t n = uint32_t(h[80]) | uint32_t(h[81]) << 8 | uint32_t(h[82]) << 16 | uint32_t(h[83]) << 24;
    if (size >= 84 && size == 84 + 50 * uintmax_t(n)) return too_many_triangles(n);
    size_t first = 0;
    while (first < sizeof h && std::isspace(h[first])) ++first;
    if (first + 5 > sizeof h || std::memcmp(h + first, "solid", 5) != 0) {
      if (size < 84) return fmt::format("it is neither an ASCII STL (which starts with 'solid') nor a binary STL (at least 84 bytes; it has {})", size);
      return fmt::format("it is neither an ASCII STL (which starts with 'solid') nor a binary STL: its header promises {} triangles "
                         "({} bytes), the file has {} bytes (truncated or corrupt)", n, 84 + 50 * uintmax_t(n), size);
    }
  }
  if (ext == ".glb") {
    // Header: magic "glTF", version 2, total length; then a JSON chunk (length, "JSON").
    std::ifstream in(path, std::ios::binary);
    unsigned char h[20] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    auto u32 = [&](int at) { return uint32_t(h[at]) | uint32_t(h[at + 1]) << 8 | uint32_t(h[at + 2]) << 16 | uint32_t(h[at + 3]) << 24; };
    if (in.gcount() < 20 || std::memcmp(h, "glTF", 4) != 0) return "not a binary glTF file (no 'glTF' header)";
    if (u32(4) != 2) return fmt::format("binary glTF version {}, expected 2", u32(4));
    if (u32(8) != size) return fmt::format("its header says {} bytes, the file has {}: truncated or corrupt", u32(8), size);
    if (uint64_t(u32(12)) + 20 > size || std::memcmp(h + 16, "JSON", 4) != 0) return "its first chunk is no JSON chunk within the file";
  }
  return "";
}

/// What assimp made of a file: vertices as written, triangles (polygons fanned), or why not.
struct RawMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  std::vector<uint32_t> triangle_rgb;  ///< as TriangleMesh::triangle_rgb
  std::string error;  ///< non-empty: the file could not be read
  std::string warning;  ///< non-empty: read, but something in it is not drawn as the file says
  std::vector<std::string> images;  ///< as TriangleMesh::images
};

/// The diffuse colour of a material as 0x1RRGGBB; 0 for assimp's default material (a format
/// without materials) or a material without one.
uint32_t material_rgb(const aiScene* scene, unsigned index) {
  if (index >= scene->mNumMaterials) return 0;
  const aiMaterial* m = scene->mMaterials[index];
  aiString name;
  if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS && std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME) return 0;
  aiColor4D c;
  if (aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) != AI_SUCCESS) return 0;
  auto byte = [](float x) { return static_cast<uint32_t>(std::lround(std::clamp(std::isfinite(x) ? x : 0.0f, 0.0f, 1.0f) * 255)); };
  return 0x1000000u | byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
}

/// The textures of one file's materials, each read once. A texture that cannot be read leaves its
/// triangles uncoloured, with a warning: drawn in the colour the URDF material or the type gives
/// (a textured material's own diffuse colour is a loader's default grey); one outside the allowed
/// folders is an error (as every file a mesh refers to).
class Textures {
 public:
  Textures(const aiScene* scene, std::filesystem::path folder) : scene_(scene), folder_(std::move(folder)) {}

  /// The diffuse (glTF: base colour) texture of material `index`, or nullptr.
  const Texture* of_material(unsigned index, RawMesh& out) {
    if (index >= scene_->mNumMaterials) return nullptr;
    const aiMaterial* m = scene_->mMaterials[index];
    aiString name;
    if (m->GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS && m->GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS)
      return nullptr;
    auto [it, fresh] = read_.try_emplace(name.C_Str());
    if (fresh) it->second = read(name.C_Str(), out);
    if (!it->second) unread_.insert(index);
    return it->second ? &*it->second : nullptr;
  }
  /// Whether material `index` has a texture that could not be read (after of_material).
  bool unread(unsigned index) const { return unread_.count(index) > 0; }

 private:
  std::optional<Texture> read(std::string name, RawMesh& out) {
    std::string bytes, why;
    if (const aiTexture* embedded = scene_->GetEmbeddedTexture(name.c_str())) {
      if (embedded->mHeight == 0) {  // a compressed image (PNG, JPEG) of mWidth bytes
        bytes.assign(reinterpret_cast<const char*>(embedded->pcData), embedded->mWidth);
      } else {  // texels as written
        Texture t;
        if (double(embedded->mWidth) * embedded->mHeight > kMaxTexturePixels) {
          if (out.warning.empty()) out.warning = fmt::format("its embedded image {} is larger than {:.0f} pixels: drawn without it", name, kMaxTexturePixels);
          return std::nullopt;
        }
        t.width = static_cast<int>(embedded->mWidth);
        t.height = static_cast<int>(embedded->mHeight);
        for (size_t k = 0; k < size_t(embedded->mWidth) * embedded->mHeight; ++k)
          t.rgb.insert(t.rgb.end(), {embedded->pcData[k].r, embedded->pcData[k].g, embedded->pcData[k].b});
        return t;
      }
      name = "embedded image " + name;
    } else {
      if (name.rfind("file://", 0) == 0) name.erase(0, 7);
      const std::string path = std::filesystem::path(name).is_absolute() ? name : (folder_ / name).lexically_normal().string();
      if (std::string w = outside_roots(path); !w.empty()) {
        if (out.error.empty()) out.error = fmt::format("it refers to '{}', which {}", path, w);
        return std::nullopt;
      }
      std::error_code ec;
      const uintmax_t size = std::filesystem::file_size(path, ec);
      if (std::string w = not_a_file(path); !w.empty()) why = "it " + w;
      else if (!ec && size > limit_bytes("SSCS_MAX_MESH_MB", kMaxMeshFileMb)) why = "it is larger than the limit of a mesh file, SSCS_MAX_MESH_MB";
      else if (std::ifstream in{path, std::ios::binary}; !in) why = "it cannot be opened";
      else bytes.assign(std::istreambuf_iterator<char>(in), {});
      if (why.empty()) out.images.push_back(path);
      name = path;
    }
    std::optional<Texture> t;
    if (why.empty()) t = decode_texture(bytes, why);
    if (!t && out.warning.empty())
      out.warning = fmt::format("its texture '{}' cannot be used ({}): drawn without it", name, why);
    return t;
  }

  const aiScene* scene_;
  std::filesystem::path folder_;
  std::map<std::string, std::optional<Texture>> read_;
  std::set<unsigned> unread_;
};

/// The colour a textured triangle is drawn in: the texel under its centre, to 4 bits a channel
/// (a texture's gradients and noise would otherwise make a shape per texel colour).
uint32_t texel_under(const Texture& texture, const aiMesh* mesh, const aiFace& face) {
  aiVector3D uv(0, 0, 0);
  for (unsigned k = 0; k < 3; ++k) uv += mesh->mTextureCoords[0][face.mIndices[k]];
  uint32_t rgb = texture.at(uv.x / 3, uv.y / 3);
  auto nibble = [&](int shift) { return ((rgb >> shift & 0xffu) + 8) / 17 * 17 << shift; };
  return 0x1000000u | nibble(16) | nibble(8) | nibble(0);
}

/// assimp's file access, confined: a file a mesh refers to (a glTF buffer, an OBJ's .mtl) must lie
/// where the mesh itself may (outside_roots) and be a regular file (a FIFO would block for ever).
/// The first refusal is kept for the error message.
class ConfinedIO : public Assimp::DefaultIOSystem {
 public:
  bool Exists(const char* file) const override { return allowed(file) && Assimp::DefaultIOSystem::Exists(file); }
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override {
    return allowed(file) ? Assimp::DefaultIOSystem::Open(file, mode) : nullptr;
  }
  mutable std::string refused;

 private:
  bool allowed(const char* file) const {
    std::string w = why(file);
    if (!w.empty() && refused.empty()) refused = fmt::format("it refers to '{}', which {}", file, w);
    return w.empty();
  }
  static std::string why(const char* file) {
    if (std::string w = outside_roots(file); !w.empty()) return w;
    std::string w = not_a_file(file);
    return w == "does not exist" ? "" : w;  // a missing file is assimp's own error
  }
};

/// Reads `path` with assimp in this process. Polygons are fanned into triangles here: assimp's
/// own triangulation aborts the process on some malformed files (an OFF face with a stray byte).
RawMesh read_with_assimp(const std::string& path) {
  RawMesh out;
  Assimp::Importer importer;
  auto* io = new ConfinedIO;  // the importer owns it
  importer.SetIOHandler(io);
  const aiScene* scene = importer.ReadFile(path, aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (!io->refused.empty()) {  // even where assimp went on without the file (an OBJ's materials)
    out.error = io->refused;
    return out;
  }
  if (!scene || !scene->mRootNode) {
    out.error = importer.GetErrorString();
    if (out.error.empty()) out.error = "assimp read no scene";
    return out;
  }
  size_t triangles = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    for (unsigned f = 0; f < scene->mMeshes[m]->mNumFaces; ++f)
      triangles += std::max(2u, scene->mMeshes[m]->mFaces[f].mNumIndices) - 2;
  if (out.error = too_many_triangles(triangles); !out.error.empty()) return out;
  // assimp turns a Collada file's up axis (Z_UP in ROS packages) into its own Y up, and glTF is
  // Y up by its specification (Blender's exports, sscs's own); sscs's world is Z up, so their Y
  // up is turned into Z up: (x, y, z) -> (x, -z, y). (glTF used to be read as Z up: a Blender
  // model lay on its side.)
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool y_up = ext == ".dae" || ext == ".gltf" || ext == ".glb";
  Textures textures(scene, std::filesystem::path(path).parent_path());
  std::vector<const Texture*> texture_of(scene->mNumMeshes);  // of a mesh with texture coordinates
  bool coloured = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (am->HasTextureCoords(0)) texture_of[m] = textures.of_material(am->mMaterialIndex, out);
    coloured = coloured || texture_of[m] || (!textures.unread(am->mMaterialIndex) && material_rgb(scene, am->mMaterialIndex) != 0);
  }
  if (!out.error.empty()) return out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const uint32_t rgb = textures.unread(am->mMaterialIndex) ? 0 : material_rgb(scene, am->mMaterialIndex);
    auto base = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      if (y_up) out.vertices.emplace_back(as_written(p.x), -as_written(p.z), as_written(p.y));
      else out.vertices.emplace_back(as_written(p.x), as_written(p.y), as_written(p.z));
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      auto index_ok = [&](unsigned k) { return face.mIndices[k] < am->mNumVertices; };
      for (unsigned k = 2; k < face.mNumIndices; ++k)
        if (index_ok(0) && index_ok(k - 1) && index_ok(k)) {
          out.triangles.emplace_back(base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[k - 1]),
                                     base + static_cast<int>(face.mIndices[k]));
          if (coloured) out.triangle_rgb.push_back(texture_of[m] && face.mNumIndices == 3 ? texel_under(*texture_of[m], am, face) : rgb);
        }
    }
  }
  return out;
}

/// Writes and reads a RawMesh through a pipe (the child's answer to the parent).
bool write_all(int fd, const void* data, size_t size) {
  auto p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

void send(int fd, const RawMesh& mesh) {
  std::string images;  // NUL-separated
  for (const std::string& i : mesh.images) images += i + '\0';
  uint64_t counts[6] = {mesh.error.size(), mesh.vertices.size(), mesh.triangles.size(), mesh.triangle_rgb.size(), mesh.warning.size(),
                        images.size()};
  write_all(fd, counts, sizeof counts) && write_all(fd, mesh.error.data(), mesh.error.size()) &&
      write_all(fd, mesh.warning.data(), mesh.warning.size()) && write_all(fd, images.data(), images.size()) &&
      write_all(fd, mesh.vertices.data(), mesh.vertices.size() * sizeof(Eigen::Vector3d)) &&
      write_all(fd, mesh.triangles.data(), mesh.triangles.size() * sizeof(Eigen::Vector3i)) &&
      write_all(fd, mesh.triangle_rgb.data(), mesh.triangle_rgb.size() * sizeof(uint32_t));
}

/// Reads the child's answer from `fd`; false if it ended early (the child died).
bool receive(int fd, RawMesh& mesh) {
  std::string bytes;
  char buf[1 << 16];
  for (;;) {
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buf, static_cast<size_t>(n));
  }
  uint64_t counts[6];
  if (bytes.size() < sizeof counts) return false;
  std::memcpy(counts, bytes.data(), sizeof counts);
  const uint64_t need = sizeof counts + counts[0] + counts[4] + counts[5] + counts[1] * sizeof(Eigen::Vector3d) + counts[2] * sizeof(Eigen::Vector3i) +
                        counts[3] * sizeof(uint32_t);
  if (bytes.size() != need || (counts[3] != 0 && counts[3] != counts[2])) return false;
  const char* p = bytes.data() + sizeof counts;
  mesh.error.assign(p, counts[0]);
  p += counts[0];
  mesh.warning.assign(p, counts[4]);
  p += counts[4];
  for (const char* end = p + counts[5]; p < end; p += mesh.images.back().size() + 1) mesh.images.emplace_back(p, strnlen(p, end - p));
  mesh.vertices.resize(counts[1]);
  if (counts[1] > 0) std::memcpy(static_cast<void*>(mesh.vertices.data()), p, counts[1] * sizeof(Eigen::Vector3d));
  p += counts[1] * sizeof(Eigen::Vector3d);
  mesh.triangles.resize(counts[2]);
  if (counts[2] > 0) std::memcpy(static_cast<void*>(mesh.triangles.data()), p, counts[2] * sizeof(Eigen::Vector3i));
  p += counts[2] * sizeof(Eigen::Vector3i);
  mesh.triangle_rgb.resize(counts[3]);
  if (counts[3] > 0) std::memcpy(static_cast<void*>(mesh.triangle_rgb.data()), p, counts[3] * sizeof(uint32_t));
  return true;
}

/// Reads `path` with assimp in a child process, so that a file which crashes, hangs or exhausts
/// the parser (assimp asserts and aborts on some malformed files) is an input error, not the
/// end of sscs. The child may use SSCS_MAX_MESH_READ_MB of memory (default 4096) and a few
/// seconds of CPU (kMaxMeshReadSeconds).
RawMesh read_isolated(const std::string& path) {
  std::error_code ec;
  const double mb = static_cast<double>(std::filesystem::file_size(path, ec)) / 1e6;
  const auto seconds = static_cast<rlim_t>(
      std::ceil(limit("SSCS_MAX_MESH_READ_SECONDS", kMaxMeshReadSeconds + (ec ? 0.0 : 0.5 * mb))));
  int fds[2];
  if (::pipe(fds) != 0) return read_with_assimp(path);
  std::fflush(nullptr);
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return read_with_assimp(path);
  }
  if (pid == 0) {
    ::close(fds[0]);
    // An aborting importer's message goes nowhere: the parent says what happened.
    if (int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, STDERR_FILENO);
    if (kAddressSpaceLimits) {
      rlim_t bytes = static_cast<rlim_t>(limit_bytes("SSCS_MAX_MESH_READ_MB", kMaxMeshReadMb));
      rlimit as{bytes, bytes};
      ::setrlimit(RLIMIT_AS, &as);
    }
    rlimit cpu{seconds, seconds + 1};
    ::setrlimit(RLIMIT_CPU, &cpu);
    ::alarm(static_cast<unsigned>(3 * seconds));  // wall clock too: a read that blocks uses no CPU
    RawMesh mesh;
    try {
      mesh = read_with_assimp(path);
    } catch (const std::bad_alloc&) {
      mesh = RawMesh{};
      mesh.error = "reading it needs more memory than the limit (raise it with SSCS_MAX_MESH_READ_MB)";
    } catch (const std::exception& e) {
      mesh = RawMesh{};
      mesh.error = e.what();
    }
    if (mesh.error == std::bad_alloc().what())  // assimp catches it and reports its what()
      mesh.error = "reading it needs more memory than the limit (raise it with SSCS_MAX_MESH_READ_MB)";
    send(fds[1], mesh);
    ::_exit(0);
  }
  ::close(fds[1]);
  RawMesh mesh;
  bool whole = receive(fds[0], mesh);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (whole && WIFEXITED(status) && WEXITSTATUS(status) == 0) return mesh;
  mesh = RawMesh{};
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM)
    mesh.error = fmt::format("the mesh reader (assimp) took more than {} s on it (blocked on a file?)", 3 * seconds);
  else if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL))
    mesh.error = fmt::format("the mesh reader (assimp) took more than {} s of CPU on it (raise the limit with "
                             "SSCS_MAX_MESH_READ_SECONDS)", seconds);
  else if (WIFSIGNALED(status))
    mesh.error = fmt::format("the mesh reader (assimp) crashed on it ({}): the file is malformed", strsignal(WTERMSIG(status)));
  else
    mesh.error = "the mesh reader (assimp) ended without an answer: the file is malformed or needs more memory than "
                 "the limit (raise it with SSCS_MAX_MESH_READ_MB)";
  return mesh;
}

/// Whether `path` is a mesh of the standard library, shipped with sscs: read in this process, as
/// trusted as the program (a child process for a 7 kB pallet cost a fast run 10 % of its time:
/// the fork, and the copies of every page either process writes afterwards).
bool standard(const std::string& path) {
  static const std::filesystem::path library = [] {
    std::error_code ec;
    std::filesystem::path p = std::filesystem::weakly_canonical(standard_library_dir(), ec);
    return ec ? std::filesystem::path() : p;
  }();
  if (library.empty()) return false;
  std::error_code ec;
  const std::filesystem::path real = std::filesystem::weakly_canonical(path, ec);
  if (ec) return false;
  const auto [end, rest] = std::mismatch(library.begin(), library.end(), real.begin(), real.end());
  return end == library.end();
}

}  // namespace

std::shared_ptr<const TriangleMesh> MeshCache::load(const std::string& path, SourceMark where, Diagnostics& diag) {
  auto it = meshes_.find(path);
  if (it != meshes_.end()) return it->second;
  std::shared_ptr<const TriangleMesh> result;
  if (std::string why = not_a_readable_reference(path); !why.empty()) {
    diag.error(where, fmt::format("mesh file '{}' {}", path, why));
  } else if (std::string why = unfit_mesh_file(path); !why.empty()) {
    diag.error(where, fmt::format("cannot read mesh '{}': {}", path, why));
  } else if (RawMesh raw = standard(path) ? read_with_assimp(path) : read_isolated(path); !raw.error.empty()) {
    diag.error(where, fmt::format("cannot read mesh '{}': {}", path, printable(raw.error)));
  } else {
    auto mesh = std::make_shared<TriangleMesh>();
    mesh->path = path;
    mesh->vertices = std::move(raw.vertices);
    mesh->triangles = std::move(raw.triangles);
    mesh->triangle_rgb = std::move(raw.triangle_rgb);
    mesh->images = std::move(raw.images);
    if (!raw.warning.empty()) diag.warning(where, fmt::format("mesh '{}': {}", path, printable(raw.warning)));
    mesh->closed = is_closed(mesh->vertices, mesh->triangles);
    auto bad = std::find_if(mesh->vertices.begin(), mesh->vertices.end(), [](const Eigen::Vector3d& v) {
      return !v.allFinite() || v.cwiseAbs().maxCoeff() > kMaxLengthSi;
    });
    if (mesh->triangles.empty()) {
      diag.error(where, fmt::format("mesh '{}' has no triangles", path));
    } else if (bad != mesh->vertices.end()) {
      diag.error(where, fmt::format("mesh '{}' has a vertex that is {} (vertex {}: {} {} {})", path,
                                    bad->allFinite() ? fmt::format("beyond {:g} units from its origin", kMaxLengthSi)
                                    : bad->hasNaN() ? "not a number" : "infinite (or beyond the range of a float)",
                                    bad - mesh->vertices.begin() + 1, bad->x(), bad->y(), bad->z()));
    } else {
      result = std::move(mesh);
    }
  }
  meshes_[path] = result;
  return result;
}

bool is_closed(const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& triangles) {
  if (triangles.empty()) return false;
  // Weld by exact position: formats repeat a corner per face (STL) or per normal (OBJ, glTF).
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> weld(vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v)
    weld[v] = ids.try_emplace({vertices[v].x(), vertices[v].y(), vertices[v].z()}, static_cast<int>(ids.size())).first->second;
  // Every edge is run as often in one direction as in the other: the boundary of a solid,
  // consistently oriented (pieces that touch along an edge, a pallet's boards and blocks, count).
  std::map<std::pair<int, int>, int> directed;
  for (const Eigen::Vector3i& t : triangles)
    for (int k = 0; k < 3; ++k) {
      int a = weld[t[k]], b = weld[t[(k + 1) % 3]];
      if (a != b) ++directed[{a, b}];  // a degenerate triangle adds no edge
    }
  for (const auto& [edge, n] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != n) return false;
  }
  return true;
}

}  // namespace sscs
