#include "cases/output/xdmf.hpp"

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace radnet::cases {

std::string xdmfText(const std::string& h5, long nv, long nt, const std::vector<double>& times,
                     const std::vector<XdmfAttribute>& attrs) {
  std::ostringstream x;
  x.precision(17);
  const size_t P = times.empty() ? 1 : times.size();
  x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  x << "  <Grid Name=\"orbit\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t p = 0; p < P; ++p) {
    x << "   <Grid Name=\"position " << p << "\" GridType=\"Uniform\">\n";
    x << "    <Time Value=\"" << (times.empty() ? 0.0 : times[p]) << "\"/>\n";
    x << "    <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << nt << "\">\n"
      << "     <DataItem Dimensions=\"" << nt << " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << h5
      << ":/geometry/triangles</DataItem>\n    </Topology>\n";
    x << "    <Geometry GeometryType=\"XYZ\">\n     <DataItem Dimensions=\"" << nv
      << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/geometry/vertices</DataItem>\n"
      << "    </Geometry>\n";
    for (const auto& a : attrs) {
      const char* type = a.integer ? "NumberType=\"Int\" Precision=\"4\"" : "NumberType=\"Float\" Precision=\"8\"";
      x << "    <Attribute Name=\"" << a.name << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
      if (!a.per_position || times.empty()) {
        x << "     <DataItem Dimensions=\"" << nt << "\" " << type << " Format=\"HDF\">" << h5 << ":" << a.dataset
          << "</DataItem>\n";
      } else {
        // Row p of the (P, nt) dataset: start (p, 0), stride (1, 1), count (1, nt).
        x << "     <DataItem ItemType=\"HyperSlab\" Dimensions=\"1 " << nt << "\" Type=\"HyperSlab\">\n"
          << "      <DataItem Dimensions=\"3 2\" Format=\"XML\">" << p << " 0 1 1 1 " << nt << "</DataItem>\n"
          << "      <DataItem Dimensions=\"" << P << " " << nt << "\" " << type << " Format=\"HDF\">" << h5 << ":"
          << a.dataset << "</DataItem>\n     </DataItem>\n";
      }
      x << "    </Attribute>\n";
    }
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return x.str();
}

std::vector<XdmfAttribute> writeXdmfCellValues(Hdf5Writer& h5, const GeometryRunResult& r) {
  const Eigen::VectorXi& shown = r.triangle_node;
  const Eigen::Index nt = shown.size();
  std::vector<XdmfAttribute> attrs = {{"node", "/geometry/triangle_node", false, true}};
  auto spread = [&](const Eigen::MatrixXd& node_by_position) {  // (n×P) → (P×nt)
    Eigen::MatrixXd cells(node_by_position.cols(), nt);
    for (Eigen::Index t = 0; t < nt; ++t)  // an occluder's triangles belong to no node: 0 (node −1)
      cells.col(t) = shown[t] >= 0 ? Eigen::VectorXd(node_by_position.row(shown[t]).transpose())
                                   : Eigen::VectorXd::Zero(cells.rows());
    return cells;
  };
  const solver::Network& net = *r.radiative.network;
  const Eigen::MatrixXd area_node = net.area();
  h5.writeVector("/xdmf/node_area", spread(area_node).row(0).transpose(), "m^2");
  attrs.push_back({"node area [m^2]", "/xdmf/node_area", false});
  if (r.sweep) {
    const Eigen::MatrixXd flux = net.area().cwiseInverse().asDiagonal() * r.sweep->absorbed_total;
    h5.writeMatrix("/xdmf/absorbed_flux", spread(flux), "W/m^2");
    h5.writeMatrix("/xdmf/exitance_solar", spread(r.sweep->exitance_solar), "W/m^2");
    attrs.push_back({"absorbed environmental flux [W/m^2]", "/xdmf/absorbed_flux", true});
    attrs.push_back({"solar exitance [W/m^2]", "/xdmf/exitance_solar", true});
  }
  if (r.thermal && (r.sweep || r.thermal->temperature().cols() > 1)) {
    h5.writeMatrix("/xdmf/temperature", spread(r.thermal->temperature()), "K");
    attrs.push_back({"temperature [K]", "/xdmf/temperature", true});
  } else if (r.thermal) {
    h5.writeVector("/xdmf/temperature", spread(r.thermal->temperature()).row(0).transpose(), "K");
    attrs.push_back({"temperature [K]", "/xdmf/temperature", false});
  }
  return attrs;
}

std::string xdmfPathFor(const std::string& h5_path) {
  const std::filesystem::path p(h5_path);
  return (p.parent_path() / p.stem()).string() + ".xmf";
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  const std::string temp = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    if (!out) {
      std::remove(temp.c_str());
      throw std::runtime_error("cannot write '" + temp + "'");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    throw std::runtime_error("cannot rename '" + temp + "' to '" + path + "'");
  }
}

}  // namespace radnet::cases
