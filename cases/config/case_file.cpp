#include "cases/config/case_file.hpp"

namespace radnet::cases {

LoadedCase loadCase(const std::string& path) {
  const YamlDocument doc = YamlDocument::load(path);
  if (!doc.root().IsMap())
    throw doc.error(doc.root(), "expected a case: a mapping with 'name' and either 'network' or 'geometry'");
  LoadedCase c;
  if (isNetworkCase(doc) + isGeometryCase(doc) + isImportedCase(doc) > 1)
    throw doc.error(doc.root()[isGeometryCase(doc) ? "geometry" : "import"],
                    "case: give one of 'network', 'geometry' or 'import', not several");
  if (isImportedCase(doc))
    c.imported = loadImportedCase(doc);
  else if (isNetworkCase(doc))
    c.network = loadNetworkCase(doc);
  else if (isGeometryCase(doc))
    c.geometry = loadGeometryCase(doc);
  else
    throw doc.error(doc.root(), "case: missing 'geometry' (surfaces and materials), 'network' (view factors given) or "
                                "'import' (a thermal network from another tool's file)");
  return c;
}

}  // namespace radnet::cases
