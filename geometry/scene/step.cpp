#include "geometry/scene/step.hpp"

#include "geometry/scene/mesh_checks.hpp"

#ifdef RADNET_HAVE_OCCT
#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#endif

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <string>

namespace radnet::geometry {

#ifdef RADNET_HAVE_OCCT

bool stepSupported() { return true; }

namespace {

// One CAD face's triangulation, in metres, wound so that its normal is the face's (a
// reversed face's triangles turned).
MeshGroup faceSoup(const TopoDS_Face& face, int index, double scale) {
  MeshGroup g{std::to_string(index), {}};
  TopLoc_Location where;
  const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, where);
  if (tri.IsNull()) return g;
  const gp_Trsf to_model = where.Transformation();
  for (int i = 1; i <= tri->NbNodes(); ++i) {
    const gp_Pnt p = tri->Node(i).Transformed(to_model);
    g.soup.vertices.push_back(scale * Vec3(p.X(), p.Y(), p.Z()));
  }
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  for (int i = 1; i <= tri->NbTriangles(); ++i) {
    int a = 0, b = 0, c = 0;
    tri->Triangle(i).Get(a, b, c);
    if (reversed) std::swap(b, c);
    g.soup.triangles.push_back({a - 1, b - 1, c - 1});
    g.soup.element.push_back(index);
  }
  return g;
}

// The name the STEP file gives a face (its ADVANCED_FACE's label), made fit for a node name
// (letters, digits, '_' and '-'; anything else becomes '_'); empty when it gives none.
std::string stepName(const Handle(XSControl_TransferReader) & transfer, const TopoDS_Face& face) {
  if (transfer.IsNull()) return {};
  const Handle(StepRepr_RepresentationItem) item =
      Handle(StepRepr_RepresentationItem)::DownCast(transfer->EntityFromShapeResult(face, 1));
  if (item.IsNull() || item->Name().IsNull()) return {};
  std::string name = item->Name()->ToCString();
  if (name == "NONE") return {};  // what some exporters write for "no name"
  for (char& ch : name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-')) ch = '_';
  return name;
}

// The kernel's own work, in the process that runs it.
std::vector<MeshGroup> tessellate(const std::string& path, double scale, double mesh_size_m) {
  try {
    STEPControl_Reader reader;
    // The kernel converts the file's own unit to this one as it transfers the shapes.
    Interface_Static::SetCVal("xstep.cascade.unit", "M");
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      throw GeometryError(path + ": not a readable STEP file (OpenCASCADE could not parse it)");
    if (reader.TransferRoots() == 0) throw GeometryError(path + ": the STEP file holds no shape");
    const TopoDS_Shape shape = reader.OneShape();
    Bnd_Box box;
    BRepBndLib::Add(shape, box);
    if (box.IsVoid()) throw GeometryError(path + ": the STEP file holds no geometry");
    const double diagonal = std::sqrt(box.SquareExtent());
    const double deflection = mesh_size_m > 0 ? mesh_size_m / scale : 1e-3 * diagonal;
    // 0.5 rad: curved faces get at least about 13 segments a turn whatever the deflection.
    BRepMesh_IncrementalMesh mesher(shape, deflection, false, 0.5, false);
    std::vector<MeshGroup> faces;
    std::vector<std::string> names;
    const Handle(XSControl_TransferReader) transfer = reader.WS()->TransferReader();
    int index = 0;
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next(), ++index) {
      MeshGroup g = faceSoup(TopoDS::Face(e.Current()), index, scale);
      if (g.soup.triangles.empty()) continue;
      names.push_back(stepName(transfer, TopoDS::Face(e.Current())));
      faces.push_back(std::move(g));
    }
    if (faces.empty()) throw GeometryError(path + ": no face of the STEP file could be tessellated");
    // A face the file names takes its name, unless another face has it too (or it reads as
    // a number, which could be another face's index): then its index, as unnamed faces.
    for (size_t k = 0; k < faces.size(); ++k) {
      const std::string& name = names[k];
      const bool numeric = !name.empty() && std::all_of(name.begin(), name.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
      if (!name.empty() && !numeric && std::count(names.begin(), names.end(), name) == 1) faces[k].name = name;
    }
    return faces;
  } catch (const Standard_Failure& f) {
    throw GeometryError(path + ": OpenCASCADE failed on the STEP file (" + std::string(f.GetMessageString()) + ")");
  }
}

// The faces through a pipe: their count, then per face its name, vertices, triangles and
// elements, each list after its length.
template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string pack(const std::vector<MeshGroup>& faces) {
  std::string out;
  put(out, faces.size());
  for (const MeshGroup& g : faces) {
    put(out, g.name.size());
    out += g.name;
    put(out, g.soup.vertices.size());
    for (const Vec3& v : g.soup.vertices) put(out, v.x()), put(out, v.y()), put(out, v.z());
    put(out, g.soup.triangles.size());
    for (const auto& t : g.soup.triangles) put(out, t);
    for (int e : g.soup.element) put(out, e);
  }
  return out;
}

struct Unpacker {
  const std::string& in;
  size_t at = 0;
  template <class T>
  T get() {
    T v{};
    if (at + sizeof v > in.size()) throw GeometryError("the STEP reader's answer was cut short");
    std::memcpy(&v, in.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
};

std::vector<MeshGroup> unpack(const std::string& in) {
  Unpacker u{in};
  std::vector<MeshGroup> faces(u.get<size_t>());
  for (MeshGroup& g : faces) {
    const size_t name = u.get<size_t>();
    if (u.at + name > in.size()) throw GeometryError("the STEP reader's answer was cut short");
    g.name = in.substr(u.at, name);
    u.at += name;
    g.soup.vertices.resize(u.get<size_t>());
    for (Vec3& v : g.soup.vertices)
      for (int k = 0; k < 3; ++k) v[k] = u.get<double>();  // in order: arguments would be in any
    g.soup.triangles.resize(u.get<size_t>());
    for (auto& t : g.soup.triangles) t = u.get<std::array<int, 3>>();
    g.soup.element.resize(g.soup.triangles.size());
    for (int& e : g.soup.element) e = u.get<int>();
  }
  return faces;
}

std::string drain(int fd) {
  std::string out;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got > 0) out.append(buffer, static_cast<size_t>(got));
    else if (got == 0 || errno != EINTR) break;
  }
  return out;
}

void sendAll(int fd, const std::string& data) {
  for (size_t at = 0; at < data.size();) {
    const ssize_t put = ::write(fd, data.data() + at, data.size() - at);
    if (put <= 0 && errno != EINTR) return;
    if (put > 0) at += static_cast<size_t>(put);
  }
}

}  // namespace

std::vector<MeshGroup> readStep(const std::string& path, double scale, double mesh_size_m) {
  if (!(std::isfinite(scale) && scale > 0)) throw GeometryError(path + ": scale must be a finite value > 0");
  checkMeshFile(path);
  // OpenCASCADE's STEP transfer dereferences null handles on some malformed files (found by
  // fuzzing: 45 of 400 mutants of a valid box crashed it): it runs in a child process, so a
  // crash there is a refusal of the file, never of radnet.
  int fds[2];
  if (::pipe(fds) != 0) throw GeometryError(path + ": cannot start the STEP reader (" + std::strerror(errno) + ")");
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw GeometryError(path + ": cannot start the STEP reader (" + std::strerror(errno) + ")");
  }
  if (child == 0) {
    ::close(fds[0]);
    int code = 0;
    std::string answer;
    try {
      answer = pack(tessellate(path, scale, mesh_size_m));
    } catch (const std::exception& e) {
      answer = e.what();
      code = 3;
    }
    sendAll(fds[1], answer);
    ::_exit(code);  // no exit handlers: they belong to the parent
  }
  ::close(fds[1]);
  const std::string answer = drain(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    throw GeometryError(path + ": OpenCASCADE crashed on this STEP file (signal " + std::to_string(WTERMSIG(status)) +
                        "): it is malformed or uses what the kernel cannot read");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw GeometryError(WIFEXITED(status) && WEXITSTATUS(status) == 3 ? answer
                                                                      : path + ": the STEP reader failed");
  return unpack(answer);
}

#else

bool stepSupported() { return false; }

std::vector<MeshGroup> readStep(const std::string& path, double, double) {
  throw GeometryError(path + ": this radnet was built without OpenCASCADE, so it reads no STEP files "
                             "(install libocct-data-exchange-dev and rebuild)");
}

#endif

}  // namespace radnet::geometry
