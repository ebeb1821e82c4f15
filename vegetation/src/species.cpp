#include "forest/vegetation/species.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "forest/core/error.hpp"
#include "forest/core/random.hpp"

namespace forest::vegetation {
namespace {

using glm::dvec3;

struct TreeTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using Color = OpenMesh::Vec3f;
  VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Color | OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<TreeTraits>;
using VertexHandle = OMesh::VertexHandle;

// Trunks start this far below the base (y = 0) so that on sloped ground no gap shows under them.
constexpr double kRootDepth = 0.6;

const OpenMesh::Vec3f kBark(0.30f, 0.21f, 0.13f);
const OpenMesh::Vec3f kNeedles(0.10f, 0.26f, 0.12f);
const OpenMesh::Vec3f kLeaves(0.20f, 0.40f, 0.12f);
const OpenMesh::Vec3f kShrubLeaves(0.16f, 0.31f, 0.09f);

OpenMesh::Vec3d om(const dvec3& p) { return {p.x, p.y, p.z}; }

using Random = SplitMix64;  // the species layout stream

// Adds closed components to one OpenMesh mesh, tagging each face with its component.
class ComponentBuilder {
 public:
  explicit ComponentBuilder(OMesh& mesh) : mesh_(mesh) { mesh_.add_property(component_, "component"); }
  OpenMesh::FPropHandleT<int> componentProperty() const { return component_; }

  // A tube through `centres` with `radii` (one per centre), closed at both ends: a fan cap, or a
  // single apex vertex where the radius is 0. Rings use parallel-transported frames with
  // u × v = tangent, so faces (a, b, c) below are counter-clockwise seen from outside.
  void tube(const std::vector<dvec3>& centres, const std::vector<double>& radii, int segments,
            const OpenMesh::Vec3f& color) {
    const size_t n = centres.size();
    std::vector<std::vector<VertexHandle>> rings(n);
    dvec3 u(0.0);
    for (size_t k = 0; k < n; ++k) {
      const dvec3 tangent = glm::normalize(centres[std::min(k + 1, n - 1)] - centres[k > 0 ? k - 1 : 0]);
      if (k == 0) {
        const dvec3 helper = std::abs(tangent.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
        u = glm::normalize(glm::cross(helper, tangent));
      } else {
        u = glm::normalize(u - glm::dot(u, tangent) * tangent);  // parallel transport
      }
      const dvec3 v = glm::cross(tangent, u);
      if (radii[k] <= 0.0) {
        rings[k].push_back(vertex(centres[k], color));
        continue;
      }
      for (int j = 0; j < segments; ++j) {
        const double angle = 2.0 * std::numbers::pi * j / segments;
        rings[k].push_back(vertex(centres[k] + radii[k] * (std::cos(angle) * u + std::sin(angle) * v), color));
      }
    }
    for (size_t k = 0; k + 1 < n; ++k) {
      const auto& a = rings[k];
      const auto& b = rings[k + 1];
      for (int j = 0; j < segments; ++j) {
        const int next = (j + 1) % segments;
        if (a.size() == 1) {
          face(a[0], b[next], b[j]);
        } else if (b.size() == 1) {
          face(a[j], a[next], b[0]);
        } else {
          face(a[j], a[next], b[next]);
          face(a[j], b[next], b[j]);
        }
      }
    }
    if (rings.front().size() > 1) {  // bottom cap, facing −tangent
      const VertexHandle centre = vertex(centres.front(), color);
      for (int j = 0; j < segments; ++j) face(centre, rings.front()[(j + 1) % segments], rings.front()[j]);
    }
    if (rings.back().size() > 1) {  // top cap, facing +tangent
      const VertexHandle centre = vertex(centres.back(), color);
      for (int j = 0; j < segments; ++j) face(centre, rings.back()[j], rings.back()[(j + 1) % segments]);
    }
    ++current_;
  }

  // A closed lumpy blob: a latitude-longitude sphere (poles as single vertices) with radii
  // `radii` (ellipsoid) and a smooth radial bump of relative size `lumpiness`. Radial
  // displacement of a star-shaped surface cannot make it intersect itself.
  void blob(const dvec3& centre, const dvec3& radii, double lumpiness, int longitudes, int latitudes, double phase,
            const OpenMesh::Vec3f& color) {
    auto point = [&](double polar, double azimuth) {
      const dvec3 d(std::sin(polar) * std::cos(azimuth), std::cos(polar), std::sin(polar) * std::sin(azimuth));
      const double bump = 1.0 + lumpiness * (std::sin(3.0 * azimuth + phase) * std::sin(2.0 * polar + 0.7 * phase) +
                                             0.5 * std::sin(5.0 * azimuth - 1.3 * phase) * std::sin(4.0 * polar));
      return centre + bump * radii * d;
    };
    const VertexHandle top = vertex(point(0.0, 0.0), color);
    std::vector<std::vector<VertexHandle>> rings;
    for (int i = 1; i < latitudes; ++i) {
      std::vector<VertexHandle>& ring = rings.emplace_back();
      const double polar = std::numbers::pi * i / latitudes;
      for (int j = 0; j < longitudes; ++j) ring.push_back(vertex(point(polar, 2.0 * std::numbers::pi * j / longitudes), color));
    }
    const VertexHandle bottom = vertex(point(std::numbers::pi, 0.0), color);
    // Azimuth grows from +x toward +z; seen from outside (above at the top pole) that is clockwise,
    // so the winding below runs against it.
    for (int j = 0; j < longitudes; ++j) face(top, rings.front()[(j + 1) % longitudes], rings.front()[j]);
    for (size_t i = 0; i + 1 < rings.size(); ++i)
      for (int j = 0; j < longitudes; ++j) {
        const int next = (j + 1) % longitudes;
        face(rings[i][j], rings[i][next], rings[i + 1][next]);
        face(rings[i][j], rings[i + 1][next], rings[i + 1][j]);
      }
    for (int j = 0; j < longitudes; ++j) face(bottom, rings.back()[j], rings.back()[(j + 1) % longitudes]);
    ++current_;
  }

  // A closed torus about the vertical axis through `centre`: `majorSegments` × `minorSegments`
  // quads (two triangles each), counter-clockwise seen from outside.
  void torus(const dvec3& centre, double majorRadius, double minorRadius, int majorSegments, int minorSegments,
             const OpenMesh::Vec3f& color) {
    std::vector<std::vector<VertexHandle>> rings(static_cast<size_t>(majorSegments));
    for (int i = 0; i < majorSegments; ++i) {
      const double theta = 2.0 * std::numbers::pi * i / majorSegments;
      for (int j = 0; j < minorSegments; ++j) {
        const double phi = 2.0 * std::numbers::pi * j / minorSegments;
        const double reach = majorRadius + minorRadius * std::cos(phi);
        rings[static_cast<size_t>(i)].push_back(
            vertex(centre + dvec3(reach * std::cos(theta), minorRadius * std::sin(phi), reach * std::sin(theta)), color));
      }
    }
    // ∂p/∂φ × ∂p/∂θ points outward, so (i, j) → (i, j+1) → (i+1, j+1) winds counter-clockwise.
    for (int i = 0; i < majorSegments; ++i)
      for (int j = 0; j < minorSegments; ++j) {
        const auto& a = rings[static_cast<size_t>(i)];
        const auto& b = rings[static_cast<size_t>((i + 1) % majorSegments)];
        const int next = (j + 1) % minorSegments;
        face(a[j], a[next], b[next]);
        face(a[j], b[next], b[j]);
      }
    ++current_;
  }

 private:
  VertexHandle vertex(const dvec3& p, const OpenMesh::Vec3f& color) {
    const VertexHandle v = mesh_.add_vertex(om(p));
    mesh_.set_color(v, color);
    return v;
  }
  void face(VertexHandle a, VertexHandle b, VertexHandle c) {
    const auto f = mesh_.add_face(a, b, c);
    if (!f.is_valid()) throw Error("vegetation: OpenMesh refused a face (non-manifold component)");
    mesh_.property(component_, f) = current_;
  }

  OMesh& mesh_;
  OpenMesh::FPropHandleT<int> component_;
  int current_ = 0;
};

// Conifer, 12 m: a tapering trunk through five drooping cones.
void buildConifer(ComponentBuilder& b, double quality, Random& random) {
  const double height = 12.0;
  const int trunkSegments = std::max(4, static_cast<int>(std::lround(6 * quality)));
  std::vector<dvec3> trunk;
  std::vector<double> trunkRadii;
  const int trunkRings = std::max(2, static_cast<int>(std::lround(4 * quality)));
  for (int k = 0; k <= trunkRings; ++k) {
    const double t = static_cast<double>(k) / trunkRings;
    trunk.emplace_back(0.0, -kRootDepth + (0.92 * height + kRootDepth) * t, 0.0);
    trunkRadii.push_back(0.28 * (1.0 - t) + 0.06 * t);
  }
  b.tube(trunk, trunkRadii, trunkSegments, kBark);
  const int coneSegments = std::max(5, static_cast<int>(std::lround(14 * quality)));
  const int coneRings = std::max(1, static_cast<int>(std::lround(3 * quality)));
  for (int layer = 0; layer < 5; ++layer) {
    const double base = height * (0.18 + 0.15 * layer) + random.uniform(-0.2, 0.2);
    const double coneHeight = height * (0.34 - 0.035 * layer);
    const double radius = height * (0.25 - 0.038 * layer) * random.uniform(0.92, 1.08);
    const dvec3 lean(random.uniform(-0.15, 0.15), 0.0, random.uniform(-0.15, 0.15));
    std::vector<dvec3> centres;
    std::vector<double> radii;
    for (int k = 0; k <= coneRings; ++k) {
      const double t = static_cast<double>(k) / (coneRings + 1);
      centres.push_back(dvec3(0.0, base + coneHeight * t, 0.0) + lean * t);
      radii.push_back(radius * (1.0 - t) * (1.0 - 0.15 * t));  // slightly concave flanks
    }
    centres.push_back(dvec3(0.0, base + coneHeight, 0.0) + lean);
    radii.push_back(0.0);
    b.tube(centres, radii, coneSegments, kNeedles);
  }
}

// Broadleaf, 10 m: a leaning trunk that forks into three branches under a crown of lumpy blobs.
void buildBroadleaf(ComponentBuilder& b, double quality, Random& random) {
  const double height = 10.0;
  const int segments = std::max(4, static_cast<int>(std::lround(7 * quality)));
  const int rings = std::max(2, static_cast<int>(std::lround(4 * quality)));
  const dvec3 lean(random.uniform(-0.4, 0.4), 0.0, random.uniform(-0.4, 0.4));
  std::vector<dvec3> trunk;
  std::vector<double> trunkRadii;
  for (int k = 0; k <= rings; ++k) {
    const double t = static_cast<double>(k) / rings;
    trunk.push_back(dvec3(0.0, -kRootDepth + (0.5 * height + kRootDepth) * t, 0.0) + lean * (t * t));
    trunkRadii.push_back(0.32 * (1.0 - t) + 0.2 * t);
  }
  b.tube(trunk, trunkRadii, segments, kBark);
  const dvec3 fork = trunk.back() - dvec3(0.0, 0.4, 0.0);
  std::vector<dvec3> crownCentres;
  for (int branch = 0; branch < 3; ++branch) {
    const double azimuth = 2.0 * std::numbers::pi * (branch + random.uniform(-0.15, 0.15)) / 3.0;
    const dvec3 out(std::cos(azimuth), 0.0, std::sin(azimuth));
    const dvec3 tip = fork + dvec3(0.0, 0.25 * height, 0.0) + 0.22 * height * out;
    std::vector<dvec3> centres;
    std::vector<double> radii;
    for (int k = 0; k <= rings; ++k) {
      const double t = static_cast<double>(k) / rings;
      centres.push_back(fork + (tip - fork) * t + dvec3(0.0, 0.08 * height * std::sin(std::numbers::pi * t), 0.0));
      radii.push_back(0.16 * (1.0 - t) + 0.07 * t);
    }
    b.tube(centres, radii, segments, kBark);
    crownCentres.push_back(tip);
  }
  const int longitudes = std::max(6, static_cast<int>(std::lround(14 * quality)));
  const int latitudes = std::max(4, static_cast<int>(std::lround(8 * quality)));
  const dvec3 crown(lean.x, 0.76 * height, lean.z);
  crownCentres.push_back(crown);
  for (int extra = 0; extra < 3; ++extra) {
    const double azimuth = 2.0 * std::numbers::pi * (extra + 0.5) / 3.0;
    crownCentres.push_back(crown + dvec3(0.16 * height * std::cos(azimuth), random.uniform(-0.6, 0.8), 0.16 * height * std::sin(azimuth)));
  }
  for (size_t k = 0; k < crownCentres.size(); ++k) {
    const double r = height * random.uniform(0.17, 0.23);
    b.blob(crownCentres[k], dvec3(r, 0.8 * r, r), 0.12, longitudes, latitudes, random.uniform(0.0, 6.28), kLeaves);
  }
}

// Shrub, 2.2 m (the understorey): three stems leaning out from the base, each under a lumpy blob,
// and two low blobs between them — eight closed components.
void buildShrub(ComponentBuilder& b, double quality, Random& random) {
  const double height = 2.2;
  const int segments = std::max(4, static_cast<int>(std::lround(5 * quality)));
  const int longitudes = std::max(6, static_cast<int>(std::lround(12 * quality)));
  const int latitudes = std::max(4, static_cast<int>(std::lround(7 * quality)));
  for (int stem = 0; stem < 3; ++stem) {
    const double azimuth = 2.0 * std::numbers::pi * (stem + random.uniform(-0.2, 0.2)) / 3.0;
    const dvec3 out(std::cos(azimuth), 0.0, std::sin(azimuth));
    const dvec3 top = dvec3(0.0, 0.62 * height, 0.0) + 0.28 * height * out;
    b.tube({dvec3(0.0, -kRootDepth, 0.0) + 0.05 * out, 0.5 * top + dvec3(0.0, -0.1, 0.0), top}, {0.06, 0.045, 0.03}, segments, kBark);
    const double r = height * random.uniform(0.2, 0.26);
    b.blob(top + dvec3(0.0, 0.25 * r, 0.0), dvec3(r, 0.85 * r, r), 0.15, longitudes, latitudes, random.uniform(0.0, 6.28), kShrubLeaves);
  }
  for (int low = 0; low < 2; ++low) {
    const double azimuth = 2.0 * std::numbers::pi * (low + 0.25) / 2.0;
    const double r = height * random.uniform(0.17, 0.21);
    const dvec3 centre(0.22 * height * std::cos(azimuth), 0.75 * r, 0.22 * height * std::sin(azimuth));
    b.blob(centre, dvec3(r, 0.75 * r, r), 0.15, longitudes, latitudes, random.uniform(0.0, 6.28), kShrubLeaves);
  }
}

void buildAt(OMesh& mesh, Species species, double quality, std::uint64_t seed) {
  mesh = OMesh();  // fresh, with one "component" property
  ComponentBuilder builder(mesh);
  switch (species) {
    case Species::Conifer: {
      Random random(seed ^ 0xC0F1ull);
      buildConifer(builder, quality, random);
      break;
    }
    case Species::Broadleaf: {
      Random random(seed ^ 0xB70Aull);
      buildBroadleaf(builder, quality, random);
      break;
    }
    case Species::Shrub: {
      Random random(seed ^ 0x5A2Bull);
      buildShrub(builder, quality, random);
      break;
    }
  }
}

// Quadric edge collapses (Garland & Heckbert 1997) down to `faces`, refusing collapses that flip
// a face normal by more than 60°. Edge collapses that OpenMesh accepts keep a closed 2-manifold
// closed and 2-manifold.
void decimate(OMesh& mesh, int faces, double maxNormalDeviationDeg) {
  if (static_cast<int>(mesh.n_faces()) <= faces) return;
  mesh.update_face_normals();
  OpenMesh::Decimater::DecimaterT<OMesh> decimater(mesh);
  OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle flipping;
  decimater.add(quadric);
  decimater.add(flipping);
  decimater.module(quadric).unset_max_err();
  decimater.module(flipping).set_max_normal_deviation(maxNormalDeviationDeg);
  if (!decimater.initialize()) throw Error("vegetation: cannot initialise the OpenMesh decimater");
  decimater.decimate_to_faces(0, static_cast<size_t>(faces));
  mesh.garbage_collection();
}

TreeMesh exportMesh(OMesh& mesh, OpenMesh::FPropHandleT<int> component) {
  mesh.update_face_normals();
  mesh.update_vertex_normals();
  TreeMesh out;
  for (const auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    const auto n = mesh.normal(v);
    const auto c = mesh.color(v);
    out.positions.emplace_back(p[0], p[1], p[2]);
    out.normals.emplace_back(n[0], n[1], n[2]);
    out.albedo.emplace_back(c[0], c[1], c[2]);
    out.bounds.extend(dvec3(out.positions.back()));  // of the float positions that are drawn
  }
  int components = 0;
  for (const auto f : mesh.faces()) {
    for (const auto v : mesh.fv_range(f)) out.indices.push_back(static_cast<std::uint32_t>(v.idx()));
    const int c = mesh.property(component, f);
    out.faceComponent.push_back(static_cast<std::uint32_t>(c));
    components = std::max(components, c + 1);
  }
  out.components = components;
  return out;
}

}  // namespace

namespace {

// Appends to `hull` a closed convex piece: a frustum of a `sides`-sided pyramid around the y axis
// from height y0 to y1, circumscribed about the circles of radius r0 at y0 and r1 at y1 (r1 = 0:
// an apex), faces counter-clockwise seen from outside.
void addConvexPiece(TreeMesh& hull, double y0, double y1, double r0, double r1, int sides) {
  const int piece = hull.components++;
  const double circumscribed = 1.0 / std::cos(std::numbers::pi / sides);
  const auto base = static_cast<std::uint32_t>(hull.positions.size());
  auto ring = [&](double y, double r) {
    for (int j = 0; j < sides; ++j) {
      const double angle = 2.0 * std::numbers::pi * j / sides;
      hull.positions.emplace_back(static_cast<float>(r * circumscribed * std::cos(angle)), static_cast<float>(y),
                                  static_cast<float>(r * circumscribed * std::sin(angle)));
    }
  };
  ring(y0, r0);
  const bool apex = r1 <= 0.0;
  if (apex) hull.positions.emplace_back(0.0f, static_cast<float>(y1), 0.0f);
  else ring(y1, r1);
  const glm::dvec3 inside(0.0, 0.5 * (y0 + y1), 0.0);
  // Each triangle wound so that its normal points away from the axis point between the caps.
  auto face = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const glm::dvec3 pa(hull.positions[a]), pb(hull.positions[b]), pc(hull.positions[c]);
    if (glm::dot(glm::cross(pb - pa, pc - pa), (pa + pb + pc) / 3.0 - inside) < 0.0) std::swap(b, c);
    hull.indices.insert(hull.indices.end(), {a, b, c});
    hull.faceComponent.push_back(static_cast<std::uint32_t>(piece));
  };
  const auto n = static_cast<std::uint32_t>(sides);
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t next = (j + 1) % n;
    if (apex) {
      face(base + j, base + next, base + n);
    } else {
      face(base + j, base + next, base + n + next);
      face(base + j, base + n + next, base + n + j);
    }
  }
  for (std::uint32_t j = 1; j + 1 < n; ++j) {  // the caps, fans from their first corner
    face(base, base + j, base + j + 1);
    if (!apex) face(base + n, base + n + j, base + n + j + 1);
  }
  hull.normals.resize(hull.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
  hull.albedo.resize(hull.positions.size(), glm::vec3(0.0f));
  for (const glm::vec3& p : hull.positions) hull.bounds.extend(glm::dvec3(p));
}

}  // namespace

bool insideQueryHull(const TreeMesh& mesh, const TreeMesh& hull) {
  // Each piece as planes (a point on the face, its outward normal), checked to point out.
  struct Plane {
    glm::dvec3 point, normal;
  };
  std::vector<std::vector<Plane>> pieces(static_cast<size_t>(hull.components));
  std::vector<glm::dvec3> centroids(pieces.size(), glm::dvec3(0.0));
  std::vector<int> corners(pieces.size(), 0);
  for (size_t f = 0; f < hull.faceComponent.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      centroids[hull.faceComponent[f]] += glm::dvec3(hull.positions[hull.indices[3 * f + k]]);
      ++corners[hull.faceComponent[f]];
    }
  for (size_t f = 0; f < hull.faceComponent.size(); ++f) {
    const glm::dvec3 a(hull.positions[hull.indices[3 * f]]), b(hull.positions[hull.indices[3 * f + 1]]),
        c(hull.positions[hull.indices[3 * f + 2]]);
    const size_t piece = hull.faceComponent[f];
    const glm::dvec3 normal = glm::cross(b - a, c - a);
    if (glm::dot(normal, a - centroids[piece] / static_cast<double>(corners[piece])) <= 0.0) return false;  // not outward
    pieces[piece].push_back({a, glm::normalize(normal)});
  }
  auto inPiece = [&](const std::vector<Plane>& planes, const glm::dvec3& p) {
    for (const Plane& plane : planes)
      if (glm::dot(p - plane.point, plane.normal) > 0.0) return false;
    return true;
  };
  for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    bool held = false;
    for (const std::vector<Plane>& planes : pieces) {
      held = true;
      for (int k = 0; k < 3 && held; ++k) held = inPiece(planes, glm::dvec3(mesh.positions[mesh.indices[3 * t + k]]));
      if (held) break;
    }
    if (!held) return false;
  }
  return true;
}

SpeciesModel buildThesisTree(Species species) {
  // Thesis ch. 10's tree-like object, 1 m high (instances are scaled): a cone of 32 slices × 2
  // stacks with a base cap, and a torus ring of 32 × 8 segments around it.
  OMesh mesh;
  mesh.request_vertex_colors();
  mesh.request_face_normals();
  mesh.request_vertex_normals();
  ComponentBuilder b(mesh);
  const bool first = species == Species::Conifer;
  const OpenMesh::Vec3f crown = first ? OpenMesh::Vec3f(0.12f, 0.32f, 0.10f) : OpenMesh::Vec3f(0.22f, 0.38f, 0.12f);
  b.tube({dvec3(0.0, 0.0, 0.0), dvec3(0.0, 0.5, 0.0), dvec3(0.0, 1.0, 0.0)}, {0.3, 0.15, 0.0}, kThesisConeSlices, crown);
  b.torus(dvec3(0.0, 0.3, 0.0), 0.3, 0.05, kThesisTorusSegments, kThesisTorusSides, kBark);
  SpeciesModel model;
  model.species = species;
  const TreeMesh lod = exportMesh(mesh, b.componentProperty());
  for (int l = 0; l < kTreeLods; ++l) {
    model.lods[static_cast<size_t>(l)] = lod;  // one shape at every distance, as in the demo
    model.targetTriangles[static_cast<size_t>(l)] = lod.triangleCount();
  }
  // The query hull: the cone (radius 0.3 at y = 0 to its apex at 1) and the torus's ring (radius
  // 0.3 ± 0.05 at y = 0.3 ± 0.05), each circumscribed and grown by the margin.
  const double m = kThesisHullMargin;
  addConvexPiece(model.queryHull, -m, 1.0 + 2.0 * m, 0.3 + 2.0 * m, 0.0, kThesisHullSides);
  addConvexPiece(model.queryHull, 0.25 - m, 0.35 + m, 0.35 + m, 0.35 + m, kThesisHullSides);
  return model;
}

std::string_view speciesName(Species species) {
  switch (species) {
    case Species::Conifer: return "conifer";
    case Species::Broadleaf: return "broadleaf";
    case Species::Shrub: return "shrub";
  }
  return "unknown";
}

std::array<int, kTreeLods> lodTriangleTargets(int lod0Triangles) {
  return {lod0Triangles, std::max(120, lod0Triangles / 4), std::max(120, lod0Triangles / 16), std::max(48, lod0Triangles / 64)};
}

SpeciesModel buildSpecies(Species species, int lod0Triangles, std::uint64_t seed) {
  if (lod0Triangles < kMinLod0Triangles || lod0Triangles > kMaxLod0Triangles)
    throw InputError(fmt::format("vegetation.lod0_triangles = {}: expected [{}, {}]", lod0Triangles, kMinLod0Triangles,
                                 kMaxLod0Triangles));
  SpeciesModel model;
  model.species = species;
  model.targetTriangles = lodTriangleTargets(lod0Triangles);
  // Generate finer than LOD0 (≥ 1.3×), then simplify to each target.
  OMesh mesh;
  double quality = 1.0;
  for (int attempt = 0; attempt < 8; ++attempt) {
    buildAt(mesh, species, quality, seed);
    const double faces = static_cast<double>(mesh.n_faces());
    if (faces >= 1.3 * lod0Triangles) break;
    quality *= std::sqrt(1.5 * lod0Triangles / faces);
  }
  OpenMesh::FPropHandleT<int> component;
  mesh.get_property_handle(component, "component");
  // Each LOD from the previous one. A collapse can push a vertex through the far side of a thin
  // tube (a fold the local normal test cannot see): such a LOD is redone from the previous one with
  // a stricter normal-deviation limit.
  for (int lod = 0; lod < kTreeLods; ++lod) {
    OMesh attempt;
    // LOD3 (tens of pixels high) may turn normals further to reach its small budget.
    const std::vector<double> deviations =
        lod == 3 ? std::vector<double>{75.0, 60.0, 45.0, 30.0, 20.0, 10.0} : std::vector<double>{45.0, 30.0, 20.0, 10.0};
    for (double deviation : deviations) {
      attempt = mesh;
      decimate(attempt, model.targetTriangles[lod], deviation);
      model.lods[lod] = exportMesh(attempt, component);
      bool folded = false;
      for (int c = 0; c < model.lods[lod].components && !folded; ++c) folded = componentIntersectsItself(model.lods[lod], c);
      if (!folded) break;
    }
    mesh = attempt;
  }
  return model;
}

namespace {

// Does segment pq cross triangle abc (interior or boundary)? Möller–Trumbore on the segment.
bool segmentCrossesTriangle(const dvec3& p, const dvec3& q, const dvec3& a, const dvec3& b, const dvec3& c) {
  const dvec3 d = q - p, e1 = b - a, e2 = c - a;
  const dvec3 h = glm::cross(d, e2);
  const double det = glm::dot(e1, h);
  const double scale = glm::length(d) * glm::length(e1) * glm::length(e2);
  if (std::abs(det) <= 1e-12 * scale) return false;  // parallel or coplanar: not a crossing
  const dvec3 s = p - a;
  const double u = glm::dot(s, h) / det;
  if (u < 0.0 || u > 1.0) return false;
  const dvec3 qv = glm::cross(s, e1);
  const double v = glm::dot(d, qv) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = glm::dot(e2, qv) / det;
  return t > 0.0 && t < 1.0;
}

}  // namespace

bool componentIntersectsItself(const TreeMesh& mesh, int component) {
  std::vector<std::array<std::uint32_t, 3>> faces;
  std::vector<Aabb> boxes;
  for (size_t f = 0; f < mesh.faceComponent.size(); ++f) {
    if (mesh.faceComponent[f] != static_cast<std::uint32_t>(component)) continue;
    faces.push_back({mesh.indices[3 * f], mesh.indices[3 * f + 1], mesh.indices[3 * f + 2]});
    Aabb box;
    for (std::uint32_t v : faces.back()) box.extend(dvec3(mesh.positions[v]));
    boxes.push_back(box);
  }
  auto shares = [](const std::array<std::uint32_t, 3>& x, const std::array<std::uint32_t, 3>& y) {
    for (std::uint32_t a : x)
      for (std::uint32_t b : y)
        if (a == b) return true;
    return false;
  };
  for (size_t i = 0; i < faces.size(); ++i) {
    for (size_t j = i + 1; j < faces.size(); ++j) {
      const Aabb& a = boxes[i];
      const Aabb& b = boxes[j];
      if (a.max.x < b.min.x || b.max.x < a.min.x || a.max.y < b.min.y || b.max.y < a.min.y || a.max.z < b.min.z ||
          b.max.z < a.min.z)
        continue;
      if (shares(faces[i], faces[j])) continue;  // neighbours meet at their shared vertex or edge
      const auto& x = faces[i];
      const auto& y = faces[j];
      const dvec3 x0(mesh.positions[x[0]]), x1(mesh.positions[x[1]]), x2(mesh.positions[x[2]]);
      const dvec3 y0(mesh.positions[y[0]]), y1(mesh.positions[y[1]]), y2(mesh.positions[y[2]]);
      if (segmentCrossesTriangle(x0, x1, y0, y1, y2) || segmentCrossesTriangle(x1, x2, y0, y1, y2) ||
          segmentCrossesTriangle(x2, x0, y0, y1, y2) || segmentCrossesTriangle(y0, y1, x0, x1, x2) ||
          segmentCrossesTriangle(y1, y2, x0, x1, x2) || segmentCrossesTriangle(y2, y0, x0, x1, x2))
        return true;
    }
  }
  return false;
}

MeshTopology inspectMesh(const TreeMesh& mesh) {
  MeshTopology t;
  // Every directed edge once, and its reverse once: closed, 2-manifold, consistently oriented.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (size_t f = 0; f < mesh.indices.size(); f += 3)
    for (int k = 0; k < 3; ++k) ++directed[{mesh.indices[f + k], mesh.indices[f + (k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end()) ++t.boundaryEdges;
    else if (count != 1 || reverse->second != 1) ++t.nonManifoldEdges;
  }
  // Signed volume by the divergence theorem, per component and in all.
  t.componentVolumes.assign(static_cast<size_t>(mesh.components), 0.0);
  for (size_t f = 0; f < mesh.indices.size(); f += 3) {
    const dvec3 a(mesh.positions[mesh.indices[f]]), b(mesh.positions[mesh.indices[f + 1]]), c(mesh.positions[mesh.indices[f + 2]]);
    const double v = glm::dot(a, glm::cross(b, c)) / 6.0;
    t.signedVolume += v;
    t.componentVolumes[mesh.faceComponent[f / 3]] += v;
  }
  return t;
}

}  // namespace forest::vegetation
