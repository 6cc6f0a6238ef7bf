#include "cases/config/case_file.hpp"

namespace radnet::cases {

LoadedCase loadCase(const std::string& path) {
  const YamlDocument doc = YamlDocument::load(path);
  if (!doc.root().IsMap())
    throw doc.error(doc.root(), "expected a case: a mapping with 'name' and either 'network' or 'geometry'");
  LoadedCase c;
  if (isNetworkCase(doc) && isGeometryCase(doc))
    throw doc.error(doc.root()["geometry"], "case: give either 'network' or 'geometry', not both");
  if (isNetworkCase(doc))
    c.network = loadNetworkCase(doc);
  else if (isGeometryCase(doc))
    c.geometry = loadGeometryCase(doc);
  else
    throw doc.error(doc.root(), "case: missing 'geometry' (surfaces and materials) or 'network' (view factors given)");
  return c;
}

}  // namespace radnet::cases
