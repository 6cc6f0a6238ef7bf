#include "cases/xdmf.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

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
