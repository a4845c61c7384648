#include "fem/recorders.hpp"

#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"

namespace slide::fem {

namespace {

Index nearest_node(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  for (Index n = 0; n < model.node_count(); ++n) {
    const double d = (model.mesh.nodes[static_cast<std::size_t>(n)] - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = n;
    }
  }
  return best;
}

Index nearest_element(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  const int npe = model.nodes_per_element;
  for (Index e = 0; e < model.element_count(); ++e) {
    Vec2 centroid = Vec2::Zero();
    for (int k = 0; k < npe; ++k) {
      centroid += model.mesh.nodes[static_cast<std::size_t>(
          model.mesh.connectivity[static_cast<std::size_t>(e * npe + k)])];
    }
    const double d = (centroid / npe - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = e;
    }
  }
  return best;
}

void append(std::string& text, double value) {
  fmt::format_to(std::back_inserter(text), ",{}", value);
}

}  // namespace

Recorders::Recorders(const FemModel& model, const std::vector<RecorderSpec>& specs,
                     std::filesystem::path folder, const GroundMotion* motion,
                     std::vector<Index> base_nodes)
    : model_(model),
      folder_(std::move(folder)),
      motion_(motion),
      base_nodes_(std::move(base_nodes)) {
  for (const RecorderSpec& spec : specs) {
    Recorder r;
    r.name = spec.name;
    r.every = spec.every;
    for (const Vec2& p : spec.points) r.nodes.push_back(nearest_node(model, p));
    if (!spec.node_set.empty()) {
      bool found = false;
      for (const NodeSet& set : model.mesh.node_sets) {
        if (set.name != spec.node_set) continue;
        r.nodes = set.nodes;
        found = true;
      }
      if (!found) {
        throw Error("fem.recorders \"{}\": the mesh has no node set \"{}\"", spec.name,
                    spec.node_set);
      }
    }
    for (const Vec2& p : spec.elements) r.elements.push_back(nearest_element(model, p));
    r.header = "time";
    if (!r.nodes.empty()) {
      for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"})
        r.header += fmt::format(",base_{}", q);
      for (const Index n : r.nodes) {
        for (const char* suffix : {"", "_rel"}) {
          for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"}) {
            r.header += fmt::format(",n{}_{}{}", n, q, suffix);
          }
        }
      }
    }
    for (const Index e : r.elements) {
      for (const char* q : {"sxx", "syy", "szz", "sxy", "exx", "eyy", "ezz", "gxy"}) {
        r.header += fmt::format(",e{}_{}", e, q);
      }
    }
    r.header += '\n';
    recorders_.push_back(std::move(r));
  }
}

void Recorders::resume(double time, const Logger& logger) {
  for (Recorder& r : recorders_) {
    const auto path = folder_ / (r.name + ".csv");
    std::ifstream in(path);
    if (!in) {
      logger.warning("{}: not found, the recorder starts at t = {:.3f} s", path.string(), time);
      r.next = time;
      continue;
    }
    std::string line;
    std::getline(in, line);
    if (line + '\n' != r.header) {
      logger.warning("{}: other columns than the case's recorder, started again at t = {:.3f} s",
                     path.string(), time);
      r.next = time;
      continue;
    }
    double last = -std::numeric_limits<double>::infinity();
    while (std::getline(in, line)) {
      double t = 0.0;
      try {
        t = std::stod(line.substr(0, line.find(',')));
      } catch (const std::exception&) {
        break;  // a row a killed run left unfinished
      }
      if (t > time + 1e-9 * std::max(1.0, time)) break;
      r.rows += line + '\n';
      last = t;
    }
    r.next = r.every > 0.0 && std::isfinite(last) ? last + r.every : time;
  }
}

void Recorders::record(const FemState& state, double dt) {
  const double t = state.time;
  const auto due = [&](const Recorder& r) {
    return !(r.every > 0.0) || t >= r.next - 1e-9 * std::max(1.0, t);
  };
  if (std::ranges::none_of(recorders_, due)) return;
  // The base's fields as the nodes' are formed: u at t, v over the step, a at t − dt.
  Vec2 base_u = Vec2::Zero(), base_v = Vec2::Zero(), base_a = Vec2::Zero();
  if (motion_ != nullptr && dt > 0.0) {
    base_u = motion_->displacement(t);
    base_v = motion_->step_velocity(t - dt, dt);
    base_a = motion_->acceleration(t - dt);
  } else if (!base_nodes_.empty()) {
    for (const Index n : base_nodes_) {
      base_u += state.displacement[static_cast<std::size_t>(n)];
      base_v += state.velocity[static_cast<std::size_t>(n)];
      base_a += state.acceleration[static_cast<std::size_t>(n)];
    }
    const double share = 1.0 / static_cast<double>(base_nodes_.size());
    base_u *= share;
    base_v *= share;
    base_a *= share;
  }
  const int n_gauss = model_.gauss_per_element;
  for (Recorder& r : recorders_) {
    if (!due(r)) continue;
    while (r.every > 0.0 && r.next <= t + 1e-9 * std::max(1.0, t)) r.next += r.every;
    fmt::format_to(std::back_inserter(r.rows), "{}", t);
    if (!r.nodes.empty()) {
      for (const Vec2* q : {&base_u, &base_v, &base_a}) {
        append(r.rows, q->x());
        append(r.rows, q->y());
      }
      for (const Index node : r.nodes) {
        const auto n = static_cast<std::size_t>(node);
        const std::array<Vec2, 3> absolute{state.displacement[n], state.velocity[n],
                                           state.acceleration[n]};
        for (const Vec2& q : absolute) {
          append(r.rows, q.x());
          append(r.rows, q.y());
        }
        const std::array<Vec2, 3> relative{absolute[0] - base_u, absolute[1] - base_v,
                                           absolute[2] - base_a};
        for (const Vec2& q : relative) {
          append(r.rows, q.x());
          append(r.rows, q.y());
        }
      }
    }
    for (const Index e : r.elements) {
      Vec4 stress = Vec4::Zero(), strain = Vec4::Zero();
      for (int g = 0; g < n_gauss; ++g) {
        const auto gp = static_cast<std::size_t>(e * n_gauss + g);
        stress += state.stress[gp];
        strain += state.strain[gp];
      }
      for (int i = 0; i < 4; ++i) append(r.rows, stress[i] / n_gauss);
      for (int i = 0; i < 4; ++i) append(r.rows, strain[i] / n_gauss);
    }
    r.rows += '\n';
  }
}

void Recorders::write() const {
  for (const Recorder& r : recorders_) {
    write_text_atomically(folder_ / (r.name + ".csv"), r.header + r.rows);
  }
}

std::string Recorders::describe() const {
  std::string text;
  for (const Recorder& r : recorders_) {
    if (!text.empty()) text += "; ";
    text += fmt::format("{}: {} nodes, {} elements, {}", r.name, r.nodes.size(), r.elements.size(),
                        r.every > 0.0 ? fmt::format("every {} s", r.every) : "every step");
  }
  return text;
}

}  // namespace slide::fem
