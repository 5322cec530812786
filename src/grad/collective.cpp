#include "grad/collective.h"

#include <algorithm>
#include <cstring>

#include "vktg/error.h"

namespace vktg {
namespace {

// Images as bytes for the exchanges: per image its size and layers, per layer its name and pixels.
class Writer {
 public:
  template <class T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const uint8_t*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + size);
  }
  std::vector<uint8_t> bytes;
};

class Reader {
 public:
  explicit Reader(const std::vector<uint8_t>& bytes) : m_bytes(bytes) {}
  template <class T>
  T get() {
    T value;
    get(&value, sizeof(T));
    return value;
  }
  void get(void* data, size_t size) {
    if (size > m_bytes.size() - m_at) throw Error("internal: a process sent a truncated exchange");
    std::memcpy(data, m_bytes.data() + m_at, size);
    m_at += size;
  }
  bool done() const { return m_at == m_bytes.size(); }

 private:
  const std::vector<uint8_t>& m_bytes;
  size_t m_at = 0;
};

std::vector<uint8_t> packImages(const std::vector<ImageSet>& images) {
  Writer w;
  w.put(uint64_t(images.size()));
  for (const ImageSet& image : images) {
    w.put(image.width);
    w.put(image.height);
    w.put(uint64_t(image.layers.size()));
    for (const ImageLayer& layer : image.layers) {
      w.put(uint64_t(layer.name.size()));
      w.put(layer.name.data(), layer.name.size());
      w.put(uint64_t(layer.pixels.size()));
      w.put(layer.pixels.data(), layer.pixels.size() * sizeof(float));
    }
  }
  return std::move(w.bytes);
}

void unpackImages(const std::vector<uint8_t>& bytes, std::vector<ImageSet>& out) {
  Reader r(bytes);
  const uint64_t count = r.get<uint64_t>();
  for (uint64_t i = 0; i < count; ++i) {
    ImageSet image;
    image.width = r.get<uint32_t>();
    image.height = r.get<uint32_t>();
    image.layers.resize(r.get<uint64_t>());
    for (ImageLayer& layer : image.layers) {
      layer.name.resize(r.get<uint64_t>());
      r.get(layer.name.data(), layer.name.size());
      layer.pixels.resize(r.get<uint64_t>());
      r.get(layer.pixels.data(), layer.pixels.size() * sizeof(float));
    }
    out.push_back(std::move(image));
  }
  if (!r.done()) throw Error("internal: a process sent more than its images");
}

std::vector<ImageSet> unpackAll(const std::vector<std::vector<uint8_t>>& parts) {
  std::vector<ImageSet> out;
  for (const auto& part : parts) unpackImages(part, out);
  return out;
}

}  // namespace

bool Collective::any(bool flag) {
  std::vector<double> value = {flag ? 1.0 : 0.0};
  max(value);
  return value[0] > 0;
}

void Collective::agree(const std::string& error) {
  const std::vector<std::vector<uint8_t>> errors = allGather(std::vector<uint8_t>(error.begin(), error.end()));
  for (size_t r = 0; r < errors.size(); ++r) {
    if (errors[r].empty()) continue;
    m_failureAgreed = true;
    const std::string message(errors[r].begin(), errors[r].end());
    throw Error(size() > 1 ? "rank " + std::to_string(r) + ": " + message : message);
  }
}

int Collective::agreeOnInterrupt(int signal) {
  std::vector<double> largest = {double(signal)};
  max(largest);
  if (largest[0] > 0) m_failureAgreed = true;
  return int(largest[0]);
}

Share shareOf(size_t count, int rank, int size) {
  const size_t n = size_t(std::max(size, 1)), r = size_t(rank);
  const size_t base = count / n, extra = count % n;
  Share s;
  s.begin = r * base + std::min(r, extra);
  s.end = s.begin + base + (r < extra ? 1 : 0);
  return s;
}

Share shareOf(size_t count, const Collective* collective) {
  return collective ? shareOf(count, collective->rank(), collective->size()) : Share{0, count};
}

std::vector<double> allGatherDoubles(Collective& collective, const std::vector<double>& values) {
  std::vector<uint8_t> bytes(values.size() * sizeof(double));
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  std::vector<double> out;
  for (const auto& part : collective.allGather(bytes)) {
    const size_t at = out.size();
    out.resize(at + part.size() / sizeof(double));
    if (!part.empty()) std::memcpy(out.data() + at, part.data(), part.size());
  }
  return out;
}

double broadcastDouble(Collective& collective, double value) {
  std::vector<uint8_t> bytes(sizeof value);
  std::memcpy(bytes.data(), &value, sizeof value);
  collective.broadcast(bytes);
  if (bytes.size() != sizeof value) throw Error("internal: rank 0 broadcast something else than a number");
  std::memcpy(&value, bytes.data(), sizeof value);
  return value;
}

std::vector<ImageSet> allGatherImages(Collective& collective, const std::vector<ImageSet>& images) {
  return unpackAll(collective.allGather(packImages(images)));
}

std::vector<ImageSet> gatherImages(Collective& collective, const std::vector<ImageSet>& images) {
  return unpackAll(collective.gather(packImages(images)));
}

std::vector<ImageSet> gatherStackedViews(Collective& collective, const std::vector<ImageSet>& mine) {
  const std::vector<ImageSet> parts = gatherImages(collective, mine);
  if (!collective.root()) return {};
  if (parts.size() != mine.size() * size_t(collective.size()))
    throw Error("internal: processes sent different numbers of images");
  std::vector<ImageSet> out(mine.size());
  for (size_t k = 0; k < parts.size(); ++k) {
    const ImageSet& part = parts[k];
    ImageSet& into = out[k % mine.size()];
    if (part.layers.empty()) continue;  // a process without views
    if (into.layers.empty()) {
      into = part;
      continue;
    }
    if (part.width != into.width || part.layers.size() != into.layers.size())
      throw Error("internal: processes rendered views of different images");
    into.height += part.height;
    for (size_t l = 0; l < into.layers.size(); ++l)
      into.layers[l].pixels.insert(into.layers[l].pixels.end(), part.layers[l].pixels.begin(), part.layers[l].pixels.end());
  }
  return out;
}

ImageSet gatherStackedViews(Collective& collective, const ImageSet& mine) {
  std::vector<ImageSet> out = gatherStackedViews(collective, std::vector<ImageSet>{mine});
  return out.empty() ? ImageSet{} : std::move(out[0]);
}

void sumStats(Collective& collective, RenderStats& s) {
  uint64_t* counters[] = {&s.paths, &s.extensionRays, &s.shadowRays, &s.endedByGate, &s.endedByRoulette, &s.endedByDepth,
                          &s.nonFinite, &s.ellipsoidQueries, &s.ellipsoidEmpty, &s.silhouetteEdges, &s.edgeSilhouettes,
                          &s.edgeConnected, &s.gradientOverflows};
  std::vector<uint64_t> values;
  for (uint64_t* c : counters) values.push_back(*c);
  collective.sumWrapping(values);
  for (size_t k = 0; k < values.size(); ++k) *counters[k] = values[k];
}

}  // namespace vktg
