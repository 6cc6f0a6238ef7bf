#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::geometry {
namespace {

// Direction numbers v_k = m_k 2^(32−k), k = 1…32, of the first four Sobol dimensions.
// Dimension 1 is van der Corput; 2–4 from Joe & Kuo (new-joe-kuo-6.21201):
// (s, a, m) = (1, 0, {1}), (2, 1, {1, 3}), (3, 1, {1, 3, 1}).
std::array<std::array<std::uint32_t, 32>, 4> makeDirections() {
  std::array<std::array<std::uint32_t, 32>, 4> v{};
  for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);
  struct Poly {
    int s;
    unsigned a;
    std::array<unsigned, 3> m;
  };
  const Poly polys[3] = {{1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}};
  for (int d = 0; d < 3; ++d) {
    const Poly& p = polys[d];
    std::array<std::uint32_t, 32> m{};
    for (int k = 0; k < p.s; ++k) m[k] = p.m[k];
    for (int k = p.s; k < 32; ++k) {
      std::uint32_t mk = m[k - p.s] ^ (m[k - p.s] << p.s);
      for (int j = 1; j < p.s; ++j)
        if ((p.a >> (p.s - 1 - j)) & 1u) mk ^= m[k - j] << j;
      m[k] = mk;
    }
    for (int k = 0; k < 32; ++k) v[d + 1][k] = m[k] << (31 - k);
  }
  return v;
}

const std::array<std::array<std::uint32_t, 32>, 4>& directions() {
  static const auto v = makeDirections();
  return v;
}

constexpr double kTwoPow32 = 4294967296.0;

}  // namespace

std::uint64_t mixSeed(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (a + 1) + 0xBF58476D1CE4E5B9ull * (b + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::array<std::uint64_t, 4> mt19937_64FirstFour(std::uint64_t seed) {
  // Matsumoto & Nishimura's 64-bit generator as std::mt19937_64 defines it (C++ [rand.eng.mers]):
  // n = 312, m = 156, r = 31. Output i (i < 4) tempers the twisted word i, which needs
  // only the seeded words i, i + 1 and i + m: the seeding recurrence is run to word 160,
  // not 312, and no other word is twisted (a full engine's seeding and first twist were 6 %
  // of the sky kernel's cast: 32 streams a node).
  constexpr int n_needed = 156 + 4;
  constexpr std::uint64_t f = 6364136223846793005ull, a = 0xB5026F5AA96619E9ull;
  constexpr std::uint64_t lower = (1ull << 31) - 1, upper = ~lower;
  std::array<std::uint64_t, n_needed> x;
  x[0] = seed;
  for (int i = 1; i < n_needed; ++i) x[static_cast<size_t>(i)] = f * (x[static_cast<size_t>(i - 1)] ^ (x[static_cast<size_t>(i - 1)] >> 62)) + static_cast<std::uint64_t>(i);
  std::array<std::uint64_t, 4> out;
  for (size_t i = 0; i < 4; ++i) {
    const std::uint64_t y = (x[i] & upper) | (x[i + 1] & lower);
    std::uint64_t z = x[i + 156] ^ (y >> 1) ^ ((y & 1u) ? a : 0u);
    z ^= (z >> 29) & 0x5555555555555555ull;
    z ^= (z << 17) & 0x71D67FFFEDA60000ull;
    z ^= (z << 37) & 0xFFF7EEE000000000ull;
    z ^= z >> 43;
    out[i] = z;
  }
  return out;
}

Sobol4::Sobol4(std::uint64_t seed) {
  const std::array<std::uint64_t, 4> first = mt19937_64FirstFour(seed);
  for (size_t d = 0; d < 4; ++d) shift_[d] = static_cast<std::uint32_t>(first[d] >> 32);
}

void Sobol4::seek(std::uint32_t index) {
  index_ = index;
  const std::uint32_t gray = index ^ (index >> 1);
  const auto& v = directions();
  for (int d = 0; d < 4; ++d) {
    std::uint32_t x = 0;
    for (int k = 0; k < 32 && (gray >> k); ++k)
      if ((gray >> k) & 1u) x ^= v[d][k];
    state_[d] = x;
  }
}

std::array<double, 4> Sobol4::next() {
  std::array<double, 4> out;
  for (int d = 0; d < 4; ++d) out[d] = double(state_[d] ^ shift_[d]) / kTwoPow32;
  // Gray code: point i+1 differs from point i in the direction number of the lowest zero bit of i.
  const int c = __builtin_ctz(~index_);
  const auto& v = directions();
  if (c < 32)
    for (int d = 0; d < 4; ++d) state_[d] ^= v[d][c];
  ++index_;
  return out;
}

std::array<double, 4> Random4::next() {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return {u(rng_), u(rng_), u(rng_), u(rng_)};
}

NodeSampler::NodeSampler(const Scene& scene, int node) : scene_(scene) {
  const Node& n = scene.nodes()[static_cast<size_t>(node)];
  faces_ = n.faces;
  side_ = n.side;
  double acc = 0.0;
  for (int f : faces_) {
    const Face& face = scene.faces()[static_cast<size_t>(f)];
    acc += face.area_m2;
    cdf_.push_back(acc);
    const Vec3 normal = side_ * face.normal, edge = face.v[1] - face.v[0];
    tangent_.push_back((edge - edge.dot(normal) * normal).normalized());
  }
  for (double& c : cdf_) c /= acc;
  cdf_.back() = 1.0;
  const size_t m = cdf_.size();
  guide_.resize(m + 1);
  for (size_t j = 0; j <= m; ++j)
    guide_[j] = static_cast<std::int32_t>(std::upper_bound(cdf_.begin(), cdf_.end(), double(j) / double(m)) - cdf_.begin());
}

NodeSampler::Ray NodeSampler::mapPoint(double u0, double u1) const {
  size_t local = 0;
  return mapPointOn(u0, u1, local);
}

NodeSampler::Ray NodeSampler::mapPointOn(double u0, double u1, size_t& local) const {
  // u0 lies in [j/m, (j+1)/m] up to the rounding of u0·m, so the triangle std::upper_bound
  // finds over all of cdf_ lies between guide_[j − 1] and guide_[j + 2].
  const long m = static_cast<long>(cdf_.size());
  const long j = std::clamp(static_cast<long>(u0 * static_cast<double>(m)), 0L, m - 1);
  const auto from = cdf_.begin() + guide_[static_cast<size_t>(std::max(j - 1, 0L))];
  const auto to = cdf_.begin() + guide_[static_cast<size_t>(std::min(j + 2, m))];
  const size_t k = static_cast<size_t>(std::upper_bound(from, to, u0) - cdf_.begin());
  const size_t idx = std::min(k, faces_.size() - 1);
  const double lo = idx == 0 ? 0.0 : cdf_[idx - 1];
  const double width = cdf_[idx] - lo;
  const double s = width > 0 ? std::clamp((u0 - lo) / width, 0.0, 1.0) : 0.5;  // reuse u0 within the triangle
  const Face& f = scene_.faces()[static_cast<size_t>(faces_[idx])];
  // Uniform point on a triangle: (1 − √s) v0 + √s (1 − t) v1 + √s t v2.
  const double r = std::sqrt(s);
  Ray ray;
  ray.point = (1.0 - r) * f.v[0] + r * (1.0 - u1) * f.v[1] + r * u1 * f.v[2];
  ray.normal = side_ * f.normal;
  ray.face = faces_[idx];
  local = idx;
  return ray;
}

namespace {

// Cosine-weighted direction about n in the tangent frame (t0, n × t0) (Malley: uniform on the
// disc, lifted).
Vec3 cosineDirection(const std::array<double, 4>& u, const Vec3& n, const Vec3& t0) {
  const Vec3 t1 = n.cross(t0);
  const double r = std::sqrt(u[2]), phi = 2.0 * M_PI * u[3];
  const double z = std::sqrt(std::max(0.0, 1.0 - u[2]));
  return (r * std::cos(phi)) * t0 + (r * std::sin(phi)) * t1 + z * n;
}

}  // namespace

NodeSampler::Ray NodeSampler::map(const std::array<double, 4>& u) const {
  size_t local = 0;
  Ray ray = mapPointOn(u[0], u[1], local);
  ray.direction = cosineDirection(u, ray.normal, tangent_[local]);
  return ray;
}

bool raySphere(const Vec3& origin, const Vec3& dir, const Vec3& center, double radius, Vec3& hit) {
  // |o + t d − c|² = r²: t² + 2 b t + c = 0 with b = d·(o − c), c = |o − c|² − r².
  const Vec3 oc = origin - center;
  const double b = dir.dot(oc), c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return false;
  const double root = std::sqrt(disc);
  // The numerically stable near root (no cancellation when |b| ≫ root, i.e. far planets).
  double t = c > 0 ? c / (-b + root) : -b + root;
  if (b > 0 && c > 0) return false;  // sphere behind the origin
  if (!(t > 0)) return false;
  hit = origin + t * dir;
  return true;
}

}  // namespace radnet::geometry
