// SPDX-License-Identifier: GPL-3.0-or-later
#include "step_export.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <utility>

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <gp_Pnt.hxx>

namespace cagekit_step {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Invalid : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Checks one direction of a surface: degree >= 1, num > degree, knots.size() == num + degree + 1,
// finite and non-decreasing, a non-empty parameter range.
void check_direction(const std::vector<double>& knots, int degree, uint32_t num, size_t index, const char* dir) {
  auto fail = [&](const std::string& what) {
    throw Invalid("surface " + std::to_string(index) + ": " + dir + " " + what);
  };
  if (degree < 1 || degree > 25) fail("degree " + std::to_string(degree) + " outside [1, 25]");
  if (num < uint32_t(degree) + 1) fail("needs at least degree + 1 control points");
  if (knots.size() != size_t(num) + size_t(degree) + 1)
    fail("knot vector has " + std::to_string(knots.size()) + " knots, not num + degree + 1 = " +
         std::to_string(size_t(num) + size_t(degree) + 1));
  for (size_t k = 0; k < knots.size(); ++k) {
    if (!std::isfinite(knots[k])) fail("knot " + std::to_string(k) + " is not finite");
    if (k > 0 && knots[k] < knots[k - 1]) fail("knots decrease at " + std::to_string(k));
  }
  if (!(knots[size_t(degree)] < knots[size_t(num)])) fail("has an empty parameter range");
}

void check_surface(const BSplineSurface& s, size_t index) {
  check_direction(s.knots_u, s.degree_u, s.num_u, index, "u");
  check_direction(s.knots_v, s.degree_v, s.num_v, index, "v");
  if (s.points.size() != size_t(s.num_u) * s.num_v * 3)
    throw Invalid("surface " + std::to_string(index) + ": " + std::to_string(s.points.size()) +
                  " coordinates, not 3 * num_u * num_v");
  for (double c : s.points)
    if (!std::isfinite(c)) throw Invalid("surface " + std::to_string(index) + ": a control point is not finite");
}

// Full knot vector -> distinct knots + multiplicities (OCCT's form). Knots equal within a tiny
// fraction of the range are one knot.
void distinct_knots(const std::vector<double>& full, TColStd_Array1OfReal*& knots, TColStd_Array1OfInteger*& mults) {
  const double eps = 1e-14 * std::max(1.0, std::fabs(full.back() - full.front()));
  std::vector<double> values;
  std::vector<int> counts;
  for (double k : full) {
    if (!values.empty() && k - values.back() <= eps) ++counts.back();
    else {
      values.push_back(k);
      counts.push_back(1);
    }
  }
  knots = new TColStd_Array1OfReal(1, int(values.size()));
  mults = new TColStd_Array1OfInteger(1, int(values.size()));
  for (size_t i = 0; i < values.size(); ++i) {
    knots->SetValue(int(i) + 1, values[i]);
    mults->SetValue(int(i) + 1, counts[i]);
  }
}

Handle(Geom_BSplineSurface) make_surface(const BSplineSurface& s) {
  TColgp_Array2OfPnt poles(1, int(s.num_u), 1, int(s.num_v));
  for (uint32_t j = 0; j < s.num_v; ++j)
    for (uint32_t i = 0; i < s.num_u; ++i) {
      const double* p = &s.points[3 * (size_t(j) * s.num_u + i)];
      poles.SetValue(int(i) + 1, int(j) + 1, gp_Pnt(p[0], p[1], p[2]));
    }
  TColStd_Array1OfReal *uk = nullptr, *vk = nullptr;
  TColStd_Array1OfInteger *um = nullptr, *vm = nullptr;
  distinct_knots(s.knots_u, uk, um);
  distinct_knots(s.knots_v, vk, vm);
  std::unique_ptr<TColStd_Array1OfReal> uk_owner(uk), vk_owner(vk);
  std::unique_ptr<TColStd_Array1OfInteger> um_owner(um), vm_owner(vm);
  return new Geom_BSplineSurface(poles, *uk, *vk, *um, *vm, s.degree_u, s.degree_v);
}

// Largest distance between two surfaces of the same parameter domain on a 33 x 33 grid.
double grid_distance(const Handle(Geom_BSplineSurface)& a, const Handle(Geom_BSplineSurface)& b) {
  double u0, u1, v0, v1, d = 0;
  a->Bounds(u0, u1, v0, v1);
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) {
      const double u = u0 + (u1 - u0) * i / 32.0, v = v0 + (v1 - v0) * j / 32.0;
      d = std::max(d, a->Value(u, v).Distance(b->Value(u, v)));
    }
  return d;
}

// Removes the interior knots whose removal moves the surface by at most a step tolerance (OCCT
// checks each removal against the surface before it, so the moves add up): first `tolerance`
// itself, then half as much while the result, measured against the input on a 33 x 33 grid of its
// parameter domain (removal keeps the parametrisation), is further than `tolerance` (at most four
// halvings; otherwise the input is kept). Returns the measured distance of the kept surface.
double remove_knots(Handle(Geom_BSplineSurface)& surface, double tolerance) {
  const Handle(Geom_BSplineSurface) original = surface;
  double step = tolerance;
  for (int attempt = 0; attempt < 5; ++attempt, step *= 0.5) {
    Handle(Geom_BSplineSurface) s = Handle(Geom_BSplineSurface)::DownCast(original->Copy());
    for (int i = 2; i < s->NbUKnots();)
      if (!s->RemoveUKnot(i, 0, step)) ++i;
    for (int i = 2; i < s->NbVKnots();)
      if (!s->RemoveVKnot(i, 0, step)) ++i;
    if (s->NbUPoles() * s->NbVPoles() == original->NbUPoles() * original->NbVPoles()) break;
    const double moved = grid_distance(original, s);
    if (moved <= tolerance) {
      surface = s;
      return moved;
    }
  }
  surface = original;
  return 0.0;
}

uint32_t count(const TopoDS_Shape& shape, TopAbs_ShapeEnum type) {
  uint32_t n = 0;
  for (TopExp_Explorer e(shape, type); e.More(); e.Next()) ++n;
  return n;
}

// Distance from p to an axis-aligned box (0 inside).
double box_distance(const Bnd_Box& box, const gp_Pnt& p) {
  if (box.IsVoid()) return std::numeric_limits<double>::infinity();
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  const double c[3] = {p.X(), p.Y(), p.Z()};
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max({lo[i] - c[i], 0.0, c[i] - hi[i]});
    sum += d * d;
  }
  return std::sqrt(sum);
}

// OCCT's default messenger prints the STEP writer's and reader's trace on stdout (where the CLI
// writes its JSON): its stream printers are removed, once per process. Failures come back as
// return values here.
void silence_occt() {
  static const bool once = [] {
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    return true;
  }();
  (void)once;
}

std::string failure_text(const Standard_Failure& f) {
  const char* m = f.GetMessageString();
  std::string text = f.DynamicType()->Name();
  if (m && *m) text += std::string(": ") + m;
  return text;
}

// Runs body(report); any exception (OCCT's, allocation, validation) becomes report.error with
// report.ok left false: nothing is thrown out of this library.
template <class Report, class Body>
Report reported(Body&& body) {
  Report report;
  try {
    silence_occt();
    body(report);
  } catch (const Standard_Failure& f) {
    report.error = "OpenCASCADE: " + failure_text(f);
  } catch (const std::bad_alloc&) {
    report.error = "out of memory";
  } catch (const std::exception& e) {
    report.error = e.what();
  } catch (...) {
    report.error = "unknown failure";
  }
  return report;
}

}  // namespace

WriteReport write_step(const std::vector<BSplineSurface>& surfaces, const std::string& path,
                       const WriteOptions& options) {
  return reported<WriteReport>([&](WriteReport& report) {
    if (surfaces.empty()) throw Invalid("no surfaces");
    if (!(options.sewing_tolerance > 0) || !std::isfinite(options.sewing_tolerance))
      throw Invalid("sewing tolerance must be a finite number > 0");
    if (options.schema != "AP214" && options.schema != "AP203")
      throw Invalid("schema '" + options.schema + "' (AP214 or AP203)");
    for (size_t i = 0; i < surfaces.size(); ++i) check_surface(surfaces[i], i);

    Clock::time_point t = Clock::now();
    std::vector<TopoDS_Face> faces;
    faces.reserve(surfaces.size());
    const double removal = options.knot_removal_tolerance;
    if (!(removal >= 0) || !std::isfinite(removal)) throw Invalid("knot removal tolerance must be finite and >= 0");
    for (size_t i = 0; i < surfaces.size(); ++i) {
      Handle(Geom_BSplineSurface) surface = make_surface(surfaces[i]);
      report.control_points_before += uint64_t(surface->NbUPoles()) * uint64_t(surface->NbVPoles());
      const double budget = surfaces[i].knot_removal_budget < 0 ? removal
                                                                    : std::min(removal, surfaces[i].knot_removal_budget);
      if (budget > 0) report.max_knot_removal_deviation = std::max(report.max_knot_removal_deviation, remove_knots(surface, budget));
      report.control_points += uint64_t(surface->NbUPoles()) * uint64_t(surface->NbVPoles());
      BRepBuilderAPI_MakeFace make(surface, Precision::Confusion());
      if (!make.IsDone()) throw Invalid("surface " + std::to_string(i) + ": BRepBuilderAPI_MakeFace failed");
      faces.push_back(make.Face());
    }
    report.build_seconds = seconds_since(t);

    t = Clock::now();
    BRepBuilderAPI_Sewing sewing(std::max(options.sewing_tolerance, 2.5 * removal));
    for (const TopoDS_Face& f : faces) sewing.Add(f);
    sewing.Perform();
    const TopoDS_Shape sewn = sewing.SewedShape();
    report.sewing_seconds = seconds_since(t);
    if (sewn.IsNull()) throw Invalid("sewing gave no shape");
    report.free_edges = uint32_t(sewing.NbFreeEdges());
    report.multiple_edges = uint32_t(sewing.NbMultipleEdges());

    // One solid per closed shell, turned outward (the infinite point must be outside).
    t = Clock::now();
    std::vector<TopoDS_Shell> shells;
    for (TopExp_Explorer e(sewn, TopAbs_SHELL); e.More(); e.Next()) shells.push_back(TopoDS::Shell(e.Current()));
    report.shells = uint32_t(shells.size());
    const uint32_t sewn_faces = count(sewn, TopAbs_FACE);
    uint32_t faces_in_shells = 0;
    for (const TopoDS_Shell& shell : shells) faces_in_shells += count(shell, TopAbs_FACE);
    bool closed = !shells.empty() && faces_in_shells == sewn_faces && report.free_edges == 0;
    for (const TopoDS_Shell& shell : shells) closed = closed && BRep_Tool::IsClosed(shell);
    report.closed = closed;
    TopoDS_Shape result = sewn;
    if (closed) {
      std::vector<TopoDS_Solid> solids;
      for (const TopoDS_Shell& shell : shells) {
        BRepBuilderAPI_MakeSolid make(shell);
        if (!make.IsDone()) break;
        TopoDS_Solid solid = make.Solid();
        BRepClass3d_SolidClassifier classifier(solid);
        classifier.PerformInfinitePoint(Precision::Confusion());
        if (classifier.State() == TopAbs_IN) solid.Reverse();
        solids.push_back(solid);
      }
      if (solids.size() == shells.size()) {
        if (solids.size() == 1) {
          result = solids.front();
        } else {
          BRep_Builder builder;
          TopoDS_Compound compound;
          builder.MakeCompound(compound);
          for (const TopoDS_Solid& s : solids) builder.Add(compound, s);
          result = compound;
        }
        report.solid = true;
      }
    }
    report.solid_seconds = seconds_since(t);
    report.faces = count(result, TopAbs_FACE);

    t = Clock::now();
    BRepCheck_Analyzer analyzer(result);
    report.valid = analyzer.IsValid();
    report.check_seconds = seconds_since(t);

    t = Clock::now();
    // The schema parameter exists once STEPControl_Controller::Init() has registered it, and is read
    // when the writer makes its model (in its constructor).
    STEPControl_Controller::Init();
    if (!Interface_Static::SetCVal("write.step.schema", options.schema == "AP203" ? "AP203" : "AP214CD"))
      throw Invalid("OCCT does not take the STEP schema " + options.schema);
    STEPControl_Writer writer;
    if (writer.Transfer(result, STEPControl_AsIs) != IFSelect_RetDone) throw Invalid("STEP transfer failed");
    if (writer.Write(path.c_str()) != IFSelect_RetDone) throw Invalid("cannot write " + path);
    report.write_seconds = seconds_since(t);
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) throw Invalid("cannot open the written " + path);
    report.bytes = uint64_t(file.tellg());
    report.ok = true;
  });
}

ReadReport read_step(const std::string& path, const std::vector<std::array<double, 3>>& points) {
  return reported<ReadReport>([&](ReadReport& report) {
    Clock::time_point t = Clock::now();
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) throw Invalid("cannot read STEP file " + path);
    if (reader.TransferRoots() <= 0) throw Invalid("no shape in " + path);
    const TopoDS_Shape shape = reader.OneShape();
    if (shape.IsNull()) throw Invalid("no shape in " + path);
    report.read_seconds = seconds_since(t);
    report.faces = count(shape, TopAbs_FACE);
    report.shells = count(shape, TopAbs_SHELL);
    report.solids = count(shape, TopAbs_SOLID);
    report.valid = BRepCheck_Analyzer(shape).IsValid();

    t = Clock::now();
    struct FaceData {
      Handle(ShapeAnalysis_Surface) surface;
      Bnd_Box box;
    };
    std::vector<FaceData> faces;
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
      const TopoDS_Face& face = TopoDS::Face(e.Current());
      FaceData d;
      d.surface = new ShapeAnalysis_Surface(BRep_Tool::Surface(face));
      BRepBndLib::Add(face, d.box);
      faces.push_back(d);
    }
    if (faces.empty() && !points.empty()) throw Invalid("no faces to measure against in " + path);
    std::vector<std::pair<double, size_t>> order(faces.size());
    for (const std::array<double, 3>& q : points) {
      const gp_Pnt p(q[0], q[1], q[2]);
      for (size_t f = 0; f < faces.size(); ++f) order[f] = {box_distance(faces[f].box, p), f};
      std::sort(order.begin(), order.end());
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [box_distance, f] : order) {
        if (box_distance >= best) break;  // no nearer face can follow
        faces[f].surface->ValueOfUV(p, Precision::Confusion());
        best = std::min(best, faces[f].surface->Gap());
      }
      report.max_distance = std::max(report.max_distance, best);
      ++report.points_checked;
    }
    report.distance_seconds = seconds_since(t);
    report.ok = true;
  });
}

namespace {

// Index of the knot span [knots[k], knots[k+1]) holding t, k in [degree, num - 1].
size_t find_span(const std::vector<double>& knots, int degree, uint32_t num, double t) {
  size_t k = size_t(degree);
  while (k + 1 < size_t(num) && t >= knots[k + 1]) ++k;
  return k;
}

// The degree + 1 non-zero basis functions at t in span k (The NURBS Book, A2.2).
void basis(const std::vector<double>& knots, int degree, size_t k, double t, double* n) {
  double left[32], right[32];
  n[0] = 1;
  for (int j = 1; j <= degree; ++j) {
    left[j] = t - knots[k + 1 - size_t(j)];
    right[j] = knots[k + size_t(j)] - t;
    double saved = 0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom != 0 ? n[r] / denom : 0;
      n[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    n[j] = saved;
  }
}

}  // namespace

bool evaluate(const BSplineSurface& s, double u, double v, std::array<double, 3>& p) {
  try {
    check_surface(s, 0);
  } catch (const std::exception&) {
    return false;
  }
  u = std::clamp(u, s.knots_u[size_t(s.degree_u)], s.knots_u[s.num_u]);
  v = std::clamp(v, s.knots_v[size_t(s.degree_v)], s.knots_v[s.num_v]);
  const size_t ku = find_span(s.knots_u, s.degree_u, s.num_u, u), kv = find_span(s.knots_v, s.degree_v, s.num_v, v);
  double nu[32], nv[32];
  basis(s.knots_u, s.degree_u, ku, u, nu);
  basis(s.knots_v, s.degree_v, kv, v, nv);
  std::array<double, 3> sum = {0, 0, 0};
  for (int b = 0; b <= s.degree_v; ++b)
    for (int a = 0; a <= s.degree_u; ++a) {
      const size_t i = ku - size_t(s.degree_u) + size_t(a), j = kv - size_t(s.degree_v) + size_t(b);
      const double w = nu[a] * nv[b];
      for (int c = 0; c < 3; ++c) sum[size_t(c)] += w * s.points[3 * (j * s.num_u + i) + size_t(c)];
    }
  p = sum;
  return true;
}

}  // namespace cagekit_step
