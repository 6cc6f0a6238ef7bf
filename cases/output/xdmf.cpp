#include "cases/output/xdmf.hpp"

#include "cases/config/errors.hpp"
#include "cases/output/output_guard.hpp"

#include <fcntl.h>
#include <cerrno>
#include <cstring>
#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace radnet::cases {
namespace {

std::string positionName(int p) {
  std::ostringstream s;
  s << std::setw(6) << std::setfill('0') << p;
  return s.str();
}

// A label as part of a file name: anything but [A-Za-z0-9_.-] becomes '_'.
std::string fileSafe(const std::string& label) {
  std::string s = label;
  for (char& ch : s)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-')) ch = '_';
  return s;
}

// Node values (n × cols) onto a block's triangles (m), column `col`; no node: 0.
Eigen::VectorXd spread(const XdmfBlock& b, const Eigen::MatrixXd& by_node, Eigen::Index col) {
  Eigen::VectorXd cells(b.node.size());
  for (Eigen::Index t = 0; t < b.node.size(); ++t)
    cells[t] = b.node[t] >= 0 && b.node[t] < by_node.rows() ? by_node(b.node[t], col) : 0.0;
  return cells;
}

std::vector<XdmfField> fieldsOf(const GeometryRunResult& r) {
  const Eigen::VectorXd& area = r.radiative.surfaceArea();
  std::vector<XdmfField> f;
  f.push_back({"node area [m^2]", "node_area", area, false});
  if (r.sweep) {
    f.push_back({"absorbed environmental flux [W/m^2]", "absorbed_flux",
                 area.cwiseInverse().asDiagonal() * r.sweep->absorbed_total, true});
    f.push_back({"solar exitance [W/m^2]", "exitance_solar", r.sweep->exitance_solar, true});
  }
  if (r.thermal) {
    const Eigen::MatrixXd& t = r.thermal->temperature();
    f.push_back({"temperature [K]", "temperature", t, r.sweep || t.cols() > 1});
  }
  return f;
}

// The positions and times of each orbit case (or of the one run without orbit cases).
std::vector<XdmfSeries> seriesOf(const GeometryRunResult& r, const std::string& h5_path) {
  std::vector<XdmfSeries> s;
  if (r.sweep) {
    const SweepResult& sw = *r.sweep;
    for (int k = 0; k < sw.caseCount(); ++k) {
      XdmfSeries one{sw.case_labels[static_cast<size_t>(k)], "", {}, {}};
      for (int p = sw.case_start[static_cast<size_t>(k)]; p < sw.case_start[static_cast<size_t>(k) + 1]; ++p) {
        one.positions.push_back(p);
        one.times_s.push_back(sw.positions[static_cast<size_t>(p)].t_s);
      }
      s.push_back(std::move(one));
    }
  } else {
    XdmfSeries one{"", "", {}, {}};
    const bool timed = r.thermal && r.thermal->times_s.size() > 1;  // a transient without orbit
    const size_t count = timed ? r.thermal->times_s.size() : 1;
    for (size_t p = 0; p < count; ++p) {
      one.positions.push_back(static_cast<int>(p));
      one.times_s.push_back(timed ? r.thermal->times_s[p] : 0.0);
    }
    s.push_back(std::move(one));
  }
  const std::filesystem::path base(h5_path);
  const std::string stem = (base.parent_path() / base.stem()).string();
  std::set<std::string> taken;
  for (size_t k = 0; k < s.size(); ++k) {
    std::string name = s.size() == 1 ? "" : "." + fileSafe(s[k].label);
    if (!taken.insert(name).second) name += "-" + std::to_string(k);  // "a/b" and "a_b" both become "a_b"
    s[k].file = stem + name + ".xmf";
  }
  return s;
}

// Text for an XML attribute or element: a file or node name with &, <, >, " or ' in it
// (`-o 'a&b<c>.h5'`) would otherwise make the sidecar malformed XML that ParaView refuses.
std::string xml(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += ch;
    }
  }
  return out;
}

void dataItem(std::ostringstream& x, const std::string& h5, const std::string& path, Eigen::Index rows, int cols,
              bool integer) {
  x << "       <DataItem Dimensions=\"" << rows << (cols > 1 ? " " + std::to_string(cols) : "") << "\" "
    << (integer ? "NumberType=\"Int\" Precision=\"4\"" : "NumberType=\"Float\" Precision=\"8\"")
    << " Format=\"HDF\">" << xml(h5) << ":" << xml(path) << "</DataItem>\n";
}

// One block's grid at one position (`p` < 0: static fields only).
void blockGrid(std::ostringstream& x, const XdmfPlan& plan, const XdmfBlock& b, int p, const std::string& h5) {
  const std::string dir = "/xdmf/" + b.name + "/";
  const Eigen::Index m = b.node.size();
  x << "     <Grid Name=\"" << xml(b.name) << "\" GridType=\"Uniform\">\n";
  x << "      <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << m << "\">\n";
  dataItem(x, h5, dir + "triangles", m, 3, true);
  x << "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n";
  const int turned = p >= 0 && static_cast<size_t>(p) < plan.position_configuration.size()
                         ? plan.position_configuration[static_cast<size_t>(p)] : 0;
  dataItem(x, h5, turned > 0 ? "/xdmf/vertices/configuration_" + std::to_string(turned) : "/geometry/vertices",
           plan.vertices, 3, false);
  x << "      </Geometry>\n";
  auto attribute = [&](const std::string& name, const std::string& path, bool integer) {
    x << "      <Attribute Name=\"" << xml(name) << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    dataItem(x, h5, path, m, 1, integer);
    x << "      </Attribute>\n";
  };
  attribute("node", dir + "node", true);
  if (b.name == "inactive") return void(x << "     </Grid>\n");
  for (const XdmfField& f : plan.fields) {
    if (f.per_position && p < 0) continue;
    attribute(f.name, dir + f.key + (f.per_position ? "/" + positionName(p) : ""), false);
  }
  x << "     </Grid>\n";
}

}  // namespace

std::vector<XdmfBlock> xdmfBlocks(const geometry::Scene& scene) {
  const Eigen::MatrixXi tri = scene.triangleMatrix();
  const Eigen::VectorXi front = scene.frontNodes(), back = scene.backNodes();
  std::vector<XdmfBlock> blocks;
  auto collect = [&](const std::string& name, auto&& keep, bool reversed, auto&& node) {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index t = 0; t < tri.rows(); ++t)
      if (keep(t)) rows.push_back(t);
    if (rows.empty()) return;
    XdmfBlock b{name, Eigen::MatrixXi(static_cast<Eigen::Index>(rows.size()), 3),
                Eigen::VectorXi(static_cast<Eigen::Index>(rows.size()))};
    for (size_t k = 0; k < rows.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      b.triangles.row(i) = tri.row(rows[k]);
      if (reversed) std::swap(b.triangles(i, 1), b.triangles(i, 2));  // normal out of the back side
      b.node[i] = node(rows[k]);
    }
    blocks.push_back(std::move(b));
  };
  collect("front", [&](Eigen::Index t) { return front[t] >= 0; }, false, [&](Eigen::Index t) { return front[t]; });
  collect("back", [&](Eigen::Index t) { return back[t] >= 0; }, true, [&](Eigen::Index t) { return back[t]; });
  collect("inactive", [&](Eigen::Index t) { return front[t] < 0 && back[t] < 0; }, false,
          [](Eigen::Index) { return -1; });
  return blocks;
}

XdmfPlan writeXdmfData(Hdf5Writer& h5, const geometry::Scene& scene, const GeometryRunResult& r,
                       const std::string& h5_path) {
  XdmfPlan plan;
  plan.vertices = static_cast<long>(scene.vertexMatrix().rows());
  plan.blocks = xdmfBlocks(scene);
  plan.fields = fieldsOf(r);
  plan.series = seriesOf(r, h5_path);
  if (plan.series.size() > 1) plan.overview_file = xdmfPathFor(h5_path);
  if (plan.overview_file.size() && r.thermal && r.cases.envelope_max.size()) {
    plan.fields.push_back({"envelope max temperature [K]", "envelope_temperature_max", r.cases.envelope_max, false});
    plan.fields.push_back({"envelope min temperature [K]", "envelope_temperature_min", r.cases.envelope_min, false});
  }
  for (const XdmfBlock& b : plan.blocks) {
    const std::string dir = "/xdmf/" + b.name + "/";
    h5.writeIntegers(dir + "triangles", b.triangles, "1");
    h5.writeIntegers(dir + "node", b.node, "1");
    if (b.name == "inactive") continue;
    for (const XdmfField& f : plan.fields) {
      const std::string units = f.name.substr(f.name.find('[') + 1, f.name.find(']') - f.name.find('[') - 1);
      if (!f.per_position) {
        h5.writeVector(dir + f.key, spread(b, f.by_node, 0), units);
        continue;
      }
      for (const XdmfSeries& s : plan.series)
        for (int p : s.positions) h5.writeVector(dir + f.key + "/" + positionName(p), spread(b, f.by_node, p), units);
    }
  }
  if (r.articulation && r.sweep && r.articulation->vertices.size() > 1) {  // the parts at each step's angle
    plan.position_configuration = r.sweep->configuration;
    for (size_t k = 1; k < r.articulation->vertices.size(); ++k)
      h5.writeMatrix("/xdmf/vertices/configuration_" + std::to_string(k), r.articulation->vertices[k], "m");
  }
  for (XdmfField& f : plan.fields) f.by_node.resize(0, 0);  // the text needs names only
  std::vector<std::string> labels, files;
  for (const XdmfSeries& s : plan.series) {
    labels.push_back(s.label);
    files.push_back(std::filesystem::path(s.file).filename().string());
  }
  h5.writeStrings("/xdmf/series_label", labels);
  h5.writeStrings("/xdmf/series_file", files);
  return plan;
}

std::string xdmfText(const XdmfPlan& plan, int series, const std::string& h5) {
  std::ostringstream x;
  x.precision(17);
  x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  if (series < 0) {  // the overview: one step, static fields
    x << "  <Grid Name=\"geometry\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
    for (const XdmfBlock& b : plan.blocks) blockGrid(x, plan, b, -1, h5);
    x << "  </Grid>\n </Domain>\n</Xdmf>\n";
    return x.str();
  }
  const XdmfSeries& s = plan.series[static_cast<size_t>(series)];
  x << "  <Grid Name=\"" << (s.label.empty() ? "run" : xml(s.label))
    << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < s.positions.size(); ++k) {
    x << "   <Grid Name=\"position " << s.positions[k] << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
    x << "    <Time Value=\"" << s.times_s[k] << "\"/>\n";
    for (const XdmfBlock& b : plan.blocks) blockGrid(x, plan, b, s.positions[k], h5);
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return x.str();
}

std::vector<std::pair<std::string, std::string>> xdmfFiles(const XdmfPlan& plan, const std::string& h5_path) {
  const std::string h5 = std::filesystem::path(h5_path).filename().string();
  std::vector<std::pair<std::string, std::string>> files;
  for (size_t k = 0; k < plan.series.size(); ++k)
    files.emplace_back(plan.series[k].file, xdmfText(plan, static_cast<int>(k), h5));
  if (!plan.overview_file.empty()) files.emplace_back(plan.overview_file, xdmfText(plan, -1, h5));
  return files;
}

std::string xdmfPathFor(const std::string& h5_path) {
  const std::filesystem::path p(h5_path);
  return (p.parent_path() / p.stem()).string() + ".xmf";
}

}  // namespace radnet::cases
