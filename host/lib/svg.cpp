// host/lib/svg.cpp - an SVG's geometry through SVG++ (svg.h).
#include "svg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <rapidxml_ns/rapidxml_ns.hpp>
#include <svgpp/policy/xml/rapidxml_ns.hpp>
#include <svgpp/svgpp.hpp>

namespace articula::host {

namespace {

using Matrix = std::array<double, 6>;  // x' = a x + c y + e, y' = b x + d y + f: SVG's [a b c d e f]

Matrix multiply(const Matrix& m, const Matrix& n) {  // m then n inside it: m * n
  return {m[0] * n[0] + m[2] * n[1], m[1] * n[0] + m[3] * n[1], m[0] * n[2] + m[2] * n[3],
          m[1] * n[2] + m[3] * n[3], m[0] * n[4] + m[2] * n[5] + m[4], m[1] * n[4] + m[3] * n[5] + m[5]};
}

// What SVG++ hands over: the transforms of the elements entered, their geometry in absolute
// coordinates, curves as cubic Beziers (the "minimal" path policy), and what decides whether
// a shape shows (its paint, display, visibility and opacities: by attribute, or by its style
// attribute, which SVG++ reads and lets win). A shape's geometry is kept at its end only when
// it shows: a stroke or a fill that is not none, not hidden, nothing on the way transparent.
// A filled shape without a stroke is drawn as its outline, as pen plotters do.
class Context {
 public:
  explicit Context(SvgDrawing& out) : out_(out) {
    Look root;
    stack_.push_back({{1, 0, 0, 1, 0, 0}, root, false, 0});
  }

  void on_enter_element(svgpp::tag::element::any) { enter(false); }
  void on_enter_element(svgpp::tag::element::path) { enter(true); }
  void on_enter_element(svgpp::tag::element::rect) { enter(true); }
  void on_enter_element(svgpp::tag::element::circle) { enter(true); }
  void on_enter_element(svgpp::tag::element::ellipse) { enter(true); }
  void on_enter_element(svgpp::tag::element::line) { enter(true); }
  void on_enter_element(svgpp::tag::element::polyline) { enter(true); }
  void on_enter_element(svgpp::tag::element::polygon) { enter(true); }
  void on_exit_element() {
    const Level& l = stack_.back();
    if (l.shape && !l.look.shows()) {
      out_.paths.resize(l.first_path);
      ++hidden_;
    }
    stack_.pop_back();
  }
  void transform_matrix(const boost::array<double, 6>& m) {
    stack_.back().matrix = multiply(stack_.back().matrix, {m[0], m[1], m[2], m[3], m[4], m[5]});
  }
  void set_viewport(double, double, double, double) {}
  void set_viewbox_size(double, double) {}
  void disable_rendering() {}

  // Paint: none, or anything else (a colour, currentColor, a gradient): it shows.
  void set(svgpp::tag::attribute::stroke, svgpp::tag::value::none) { stack_.back().look.stroke = false; }
  void set(svgpp::tag::attribute::fill, svgpp::tag::value::none) { stack_.back().look.fill = false; }
  template <class... Value>
  void set(svgpp::tag::attribute::stroke, Value&&...) { stack_.back().look.stroke = true; }
  template <class... Value>
  void set(svgpp::tag::attribute::fill, Value&&...) { stack_.back().look.fill = true; }
  void set(svgpp::tag::attribute::display, svgpp::tag::value::none) { stack_.back().look.displayed = false; }
  void set(svgpp::tag::attribute::visibility, svgpp::tag::value::hidden) { stack_.back().look.visible = false; }
  void set(svgpp::tag::attribute::visibility, svgpp::tag::value::collapse) { stack_.back().look.visible = false; }
  void set(svgpp::tag::attribute::visibility, svgpp::tag::value::visible) { stack_.back().look.visible = true; }
  void set(svgpp::tag::attribute::visibility, svgpp::tag::value::inherit) {}
  void set(svgpp::tag::attribute::opacity, double v) { stack_.back().look.opacity *= v; }
  void set(svgpp::tag::attribute::stroke_opacity, double v) { stack_.back().look.stroke_opacity = v; }
  void set(svgpp::tag::attribute::fill_opacity, double v) { stack_.back().look.fill_opacity = v; }
  template <class Attribute, class... Value>
  void set(Attribute, Value&&...) {}  // inherit, and what else the attributes take: no change

  // Shapes left out because nothing of them shows.
  int hidden() const { return hidden_; }

  void path_move_to(double x, double y, svgpp::tag::coordinate::absolute) {
    SvgPath p;
    p.start = at(x, y);
    out_.paths.push_back(p);
    current_ = {x, y};
    subpath_start_ = current_;
  }
  void path_line_to(double x, double y, svgpp::tag::coordinate::absolute) {
    const Point2 a = at(current_.x, current_.y), b = at(x, y);
    add({Point2{a.x + (b.x - a.x) / 3, a.y + (b.y - a.y) / 3}, Point2{a.x + 2 * (b.x - a.x) / 3, a.y + 2 * (b.y - a.y) / 3}, b});
    current_ = {x, y};
  }
  void path_cubic_bezier_to(double x1, double y1, double x2, double y2, double x, double y,
                            svgpp::tag::coordinate::absolute) {
    add({at(x1, y1), at(x2, y2), at(x, y)});
    current_ = {x, y};
  }
  void path_close_subpath() {
    if (out_.paths.empty()) return;
    if (current_.x != subpath_start_.x || current_.y != subpath_start_.y)
      path_line_to(subpath_start_.x, subpath_start_.y, svgpp::tag::coordinate::absolute());
    out_.paths.back().closed = true;
    // a path goes on from its subpath's start after a close
    SvgPath p;
    p.start = at(subpath_start_.x, subpath_start_.y);
    out_.paths.push_back(p);
    current_ = subpath_start_;
  }
  void path_exit() {}

 private:
  // What decides whether a shape shows, as inherited: stroke, fill, visibility and the paint
  // opacities pass down; display:none and an opacity hide the subtree (so they pass down too).
  struct Look {
    bool stroke = false, fill = true;  // SVG's initial values: no stroke, a black fill
    bool visible = true, displayed = true;
    double opacity = 1, stroke_opacity = 1, fill_opacity = 1;
    bool shows() const {
      return displayed && visible && opacity > 0 && ((stroke && stroke_opacity > 0) || (fill && fill_opacity > 0));
    }
  };
  struct Level {
    Matrix matrix;
    Look look;
    bool shape;
    size_t first_path;  // out_.paths when it began: a shape that does not show drops what it added
  };

  void enter(bool shape) {
    Level l = stack_.back();
    l.shape = shape;
    l.first_path = out_.paths.size();
    stack_.push_back(l);
  }

  Point2 at(double x, double y) const {
    const Matrix& m = stack_.back().matrix;
    return {m[0] * x + m[2] * y + m[4], -(m[1] * x + m[3] * y + m[5])};  // y up
  }
  void add(const std::array<Point2, 3>& c) {
    if (out_.paths.empty()) {
      SvgPath p;
      p.start = at(current_.x, current_.y);
      out_.paths.push_back(p);
    }
    out_.paths.back().cubics.push_back(c);
  }

  SvgDrawing& out_;
  std::vector<Level> stack_;
  int hidden_ = 0;
  Point2 current_{0, 0}, subpath_start_{0, 0};
};

// What SVG++ would throw for, a browser passes by: an attribute or a style property it does
// not know (aria-hidden, data-*, mix-blend-mode, ...), an element it does not know. They do not
// change what is drawn; everything else it refuses still is.
template <class Ctx>
struct PassUnknown : svgpp::policy::error::raise_exception<Ctx> {
  template <class XMLElement, class ElementName>
  static bool unknown_element(const Ctx&, const XMLElement&, const ElementName&) { return true; }  // skipped
  template <class XMLAttribute, class AttributeName>
  static bool unknown_attribute(const Ctx&, const XMLAttribute&, const AttributeName&,
                                BOOST_SCOPED_ENUM(svgpp::detail::namespace_id), svgpp::tag::source::attribute) {
    return true;
  }
  template <class XMLAttribute, class AttributeName>
  static bool unknown_attribute(const Ctx&, const XMLAttribute&, const AttributeName&, svgpp::tag::source::css) {
    return true;
  }
};

typedef boost::mpl::set<svgpp::tag::element::svg, svgpp::tag::element::g, svgpp::tag::element::circle,
                        svgpp::tag::element::ellipse, svgpp::tag::element::line, svgpp::tag::element::path,
                        svgpp::tag::element::polygon, svgpp::tag::element::polyline, svgpp::tag::element::rect>::type
    processed_elements_t;

typedef boost::mpl::fold<
    boost::mpl::protect<boost::mpl::joint_view<svgpp::traits::shapes_attributes_by_element, svgpp::traits::viewport_attributes>>,
    boost::mpl::set<svgpp::tag::attribute::transform, svgpp::tag::attribute::stroke, svgpp::tag::attribute::fill,
                    svgpp::tag::attribute::display, svgpp::tag::attribute::visibility, svgpp::tag::attribute::opacity,
                    svgpp::tag::attribute::stroke_opacity, svgpp::tag::attribute::fill_opacity>::type,
    boost::mpl::insert<boost::mpl::_1, boost::mpl::_2>>::type
    processed_attributes_t;

bool starts_with_ci(const char* s, size_t n, const char* prefix) {
  const size_t k = std::strlen(prefix);
  if (n < k) return false;
  for (size_t i = 0; i < k; ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
  return true;
}

// Refuses what could run or reach outside the file, element by element.
void check_node(const rapidxml_ns::xml_node<>* n, const std::string& name) {
  for (; n; n = n->next_sibling()) {
    if (n->type() != rapidxml_ns::node_element) continue;
    const std::string local(n->local_name(), n->local_name_size());
    if (local == "script") throw SvgError(name + ": holds a <script>: a drawing never runs code");
    if (local == "foreignObject") throw SvgError(name + ": holds a <foreignObject> (HTML inside the drawing): not drawn");
    for (const rapidxml_ns::xml_attribute<>* a = n->first_attribute(); a; a = a->next_attribute()) {
      const std::string attr(a->local_name(), a->local_name_size());
      if (starts_with_ci(a->local_name(), a->local_name_size(), "on"))
        throw SvgError(name + ": <" + local + "> has an event handler (" + attr + "): a drawing never runs code");
      if (attr == "href" && !(a->value_size() > 0 && a->value()[0] == '#'))
        throw SvgError(name + ": <" + local + "> refers to something outside the file (" +
                       std::string(a->value(), std::min<size_t>(a->value_size(), 80)) + "): nothing is fetched");
      const std::string value(a->value(), a->value_size());
      if (value.find("url(") != std::string::npos && value.find("url(#") == std::string::npos)
        throw SvgError(name + ": <" + local + "> refers to something outside the file (" + value.substr(0, 80) +
                       "): nothing is fetched");
    }
    check_node(n->first_node(), name);
  }
}

const int kMaxUseDepth = 8;           // <use> in a <use> in ...
const size_t kMaxUseNodes = 20000;     // elements the <use>s of a file may copy in all

std::string local_of(const rapidxml_ns::xml_base<>* n) { return std::string(n->local_name(), n->local_name_size()); }

// A deep copy of a node, namespaces kept (rapidxml_ns's clone_node drops them, and SVG++ reads
// only elements in SVG's namespace). `budget`: nodes left to copy in the whole file.
rapidxml_ns::xml_node<>* copy_of(rapidxml_ns::xml_document<>& doc, const rapidxml_ns::xml_node<>* src, size_t& budget,
                                 const std::string& name) {
  if (budget == 0) throw SvgError(name + ": its <use> elements copy more than " + std::to_string(kMaxUseNodes) + " elements: refused");
  --budget;
  rapidxml_ns::xml_node<>* out = doc.allocate_node(src->type());
  out->qname(src->name(), src->name_size(), src->local_name());
  out->value(src->value(), src->value_size());
  out->namespace_uri(src->namespace_uri(), src->namespace_uri_size());
  for (const rapidxml_ns::xml_node<>* c = src->first_node(); c; c = c->next_sibling()) out->append_node(copy_of(doc, c, budget, name));
  for (const rapidxml_ns::xml_attribute<>* a = src->first_attribute(); a; a = a->next_attribute()) {
    rapidxml_ns::xml_attribute<>* b = doc.allocate_attribute();
    b->qname(a->name(), a->name_size(), a->local_name());
    b->value(a->value(), a->value_size());
    b->namespace_uri(a->namespace_uri(), a->namespace_uri_size());
    out->append_attribute(b);
  }
  return out;
}

// <use href="#id">: the element it names drawn in its place, as a <g> that carries the use's
// own attributes (style, transform) and its x and y as a translation, holding a copy of that
// element (a <symbol>'s children; its viewBox is not read). Uses inside the copy expand in turn,
// up to kMaxUseDepth deep; one that names itself or an ancestor is refused. What sits in <defs>,
// <symbol>, <clipPath>, <mask> or <marker> is drawn only this way: the traversal skips them.
void expand_uses(rapidxml_ns::xml_document<>& doc, rapidxml_ns::xml_node<>* root, const std::string& name) {
  std::map<std::string, const rapidxml_ns::xml_node<>*> ids;
  std::function<void(const rapidxml_ns::xml_node<>*)> index = [&](const rapidxml_ns::xml_node<>* n) {
    for (; n; n = n->next_sibling()) {
      if (n->type() != rapidxml_ns::node_element) continue;
      for (const rapidxml_ns::xml_attribute<>* a = n->first_attribute(); a; a = a->next_attribute())
        if (local_of(a) == "id") ids.emplace(std::string(a->value(), a->value_size()), n);
      index(n->first_node());
    }
  };
  index(root);
  size_t budget = kMaxUseNodes;
  std::function<void(rapidxml_ns::xml_node<>*, int)> expand = [&](rapidxml_ns::xml_node<>* parent, int depth) {
    for (rapidxml_ns::xml_node<>* n = parent->first_node(); n;) {
      rapidxml_ns::xml_node<>* next = n->next_sibling();
      if (n->type() != rapidxml_ns::node_element) {
        n = next;
        continue;
      }
      if (local_of(n) != "use") {
        expand(n, depth);
        n = next;
        continue;
      }
      if (depth >= kMaxUseDepth)
        throw SvgError(name + ": <use> inside <use> more than " + std::to_string(kMaxUseDepth) + " deep (one that names itself?): refused");
      std::string ref, x = "0", y = "0", transform;
      rapidxml_ns::xml_node<>* g = doc.allocate_node(rapidxml_ns::node_element);
      g->qname("g", 1, "g" );
      g->namespace_uri(n->namespace_uri(), n->namespace_uri_size());
      for (const rapidxml_ns::xml_attribute<>* a = n->first_attribute(); a; a = a->next_attribute()) {
        const std::string k = local_of(a), v(a->value(), a->value_size());
        if (k == "href") ref = v;
        else if (k == "x") x = v;
        else if (k == "y") y = v;
        else if (k == "transform") transform = v;
        else if (k != "width" && k != "height" && k != "id") {
          rapidxml_ns::xml_attribute<>* b = doc.allocate_attribute();
          b->qname(a->name(), a->name_size(), a->local_name());
          b->value(a->value(), a->value_size());
          b->namespace_uri(a->namespace_uri(), a->namespace_uri_size());
          g->append_attribute(b);
        }
      }
      const auto it = ref.size() > 1 ? ids.find(ref.substr(1)) : ids.end();
      if (it != ids.end()) {
        for (const rapidxml_ns::xml_node<>* up = n; up; up = up->parent())
          if (up == it->second) throw SvgError(name + ": <use href=\"" + ref.substr(0, 80) + "\"> sits inside what it names: refused");
        const std::string t = transform + " translate(" + x + " " + y + ")";
        g->append_attribute(doc.allocate_attribute("transform", doc.allocate_string(t.c_str(), t.size() + 1)));
        if (local_of(it->second) == "symbol") {
          for (const rapidxml_ns::xml_node<>* c = it->second->first_node(); c; c = c->next_sibling()) g->append_node(copy_of(doc, c, budget, name));
        } else {
          g->append_node(copy_of(doc, it->second, budget, name));
        }
        expand(g, depth + 1);
      }  // (a use that names nothing draws nothing, as in a browser)
      parent->insert_node(n, g);
      parent->remove_node(n);
      n = next;
    }
  };
  expand(root, 0);
}

// The shapes kept out of sight in <defs>, <symbol>, <clipPath>, <mask> or <marker> (after the
// uses are expanded): for the message of a file in which nothing shows.
int kept_out_of_sight(const rapidxml_ns::xml_node<>* n, bool inside) {
  static const std::set<std::string> kKeepers = {"defs", "symbol", "clipPath", "mask", "marker"};
  static const std::set<std::string> kShapes = {"path", "rect", "circle", "ellipse", "line", "polyline", "polygon"};
  int count = 0;
  for (; n; n = n->next_sibling()) {
    if (n->type() != rapidxml_ns::node_element) continue;
    const std::string local = local_of(n);
    if (inside && kShapes.count(local)) ++count;
    count += kept_out_of_sight(n->first_node(), inside || kKeepers.count(local) > 0);
  }
  return count;
}

// A <style> sheet's class rules (".frame { stroke: none; fill: none }", a selector list of
// classes), put into each element of that class as the start of its style attribute: its own
// style comes after them and wins, and both win over presentation attributes, as in CSS.
// Other selectors are not read (icon sets use classes, when they use a sheet at all).
void apply_class_rules(rapidxml_ns::xml_document<>& doc, rapidxml_ns::xml_node<>* root) {
  std::vector<std::pair<std::string, std::string>> rules;  // class, declarations
  std::function<void(rapidxml_ns::xml_node<>*)> sheets = [&](rapidxml_ns::xml_node<>* n) {
    for (; n; n = n->next_sibling()) {
      if (n->type() != rapidxml_ns::node_element) continue;
      if (std::string(n->local_name(), n->local_name_size()) == "style") {
        std::string css;
        for (rapidxml_ns::xml_node<>* t = n->first_node(); t; t = t->next_sibling())
          if (t->type() == rapidxml_ns::node_data || t->type() == rapidxml_ns::node_cdata)
            css.append(t->value(), t->value_size());
        size_t at = 0;
        while (true) {
          const size_t open = css.find('{', at), close = css.find('}', open == std::string::npos ? at : open);
          if (open == std::string::npos || close == std::string::npos) break;
          const std::string decls = css.substr(open + 1, close - open - 1);
          std::stringstream selectors(css.substr(at, open - at));
          std::string sel;
          while (std::getline(selectors, sel, ',')) {
            const size_t b = sel.find_first_not_of(" \t\r\n"), e = sel.find_last_not_of(" \t\r\n");
            if (b == std::string::npos) continue;
            sel = sel.substr(b, e - b + 1);
            if (sel.size() > 1 && sel[0] == '.' && sel.find_first_of(" .#:[>+~", 1) == std::string::npos)
              rules.emplace_back(sel.substr(1), decls);
          }
          at = close + 1;
        }
      }
      sheets(n->first_node());
    }
  };
  sheets(root);
  if (rules.empty()) return;
  std::function<void(rapidxml_ns::xml_node<>*)> apply = [&](rapidxml_ns::xml_node<>* n) {
    for (; n; n = n->next_sibling()) {
      if (n->type() != rapidxml_ns::node_element) continue;
      rapidxml_ns::xml_attribute<>* cls = n->first_attribute("class");
      if (cls) {
        std::stringstream names(std::string(cls->value(), cls->value_size()));
        std::string name, decls;
        while (names >> name)
          for (const auto& r : rules)
            if (r.first == name) decls += r.second + ";";
        if (!decls.empty()) {
          rapidxml_ns::xml_attribute<>* style = n->first_attribute("style");
          const std::string text = decls + (style ? std::string(style->value(), style->value_size()) : "");
          const char* value = doc.allocate_string(text.c_str(), text.size() + 1);
          if (style)
            style->value(value, text.size());
          else
            n->append_attribute(doc.allocate_attribute("style", value, 5, text.size()));
        }
      }
      apply(n->first_node());
    }
  };
  apply(root);
}

void grow(Bounds& b, bool& any, Point2 p) {
  if (!any) b = {p.x, p.y, p.x, p.y};
  any = true;
  b.min_x = std::min(b.min_x, p.x), b.max_x = std::max(b.max_x, p.x);
  b.min_y = std::min(b.min_y, p.y), b.max_y = std::max(b.max_y, p.y);
}

// A cubic flattened: subdivided until its control points are within `tol` of its chord.
void flatten_cubic(Point2 p0, Point2 p1, Point2 p2, Point2 p3, double tol, Stroke& out, int depth = 0) {
  const double dx = p3.x - p0.x, dy = p3.y - p0.y, len = std::hypot(dx, dy);
  auto off = [&](Point2 p) {
    return len > 1e-12 ? std::fabs((p.x - p0.x) * dy - (p.y - p0.y) * dx) / len : std::hypot(p.x - p0.x, p.y - p0.y);
  };
  if (depth >= 16 || std::max(off(p1), off(p2)) <= tol) {
    out.push_back(p3);
    return;
  }
  auto mid = [](Point2 a, Point2 b) { return Point2{(a.x + b.x) / 2, (a.y + b.y) / 2}; };
  const Point2 a = mid(p0, p1), b = mid(p1, p2), c = mid(p2, p3), ab = mid(a, b), bc = mid(b, c), m = mid(ab, bc);
  flatten_cubic(p0, a, ab, m, tol, out, depth + 1);
  flatten_cubic(m, bc, c, p3, tol, out, depth + 1);
}

}  // namespace

SvgDrawing read_svg(const std::string& text, const std::string& name) {
  if (text.size() > kMaxSvgBytes)
    throw SvgError(name + ": " + std::to_string(text.size() / 1024) + " KB: a drawing is at most 5 MB");
  // rapidxml expands no entity but the five of XML; a DOCTYPE with declarations is refused
  // before it is read (the way into an XML bomb or an outside file)
  const size_t doctype = text.find("<!DOCTYPE");
  if (text.find("<!ENTITY") != std::string::npos || (doctype != std::string::npos && text.find('[', doctype) != std::string::npos &&
                                                     text.find('[', doctype) < text.find('>', doctype)))
    throw SvgError(name + ": declares entities (a DOCTYPE with declarations): refused, as an XML bomb would be");
  std::vector<char> buf(text.begin(), text.end());
  buf.push_back('\0');
  rapidxml_ns::xml_document<> doc;
  try {
    doc.parse<rapidxml_ns::parse_no_entity_translation>(buf.data());
  } catch (const rapidxml_ns::parse_error& e) {
    throw SvgError(name + ": not an SVG file: " + e.what() + " at byte " + std::to_string(e.where<char>() - buf.data()));
  }
  const rapidxml_ns::xml_node<>* root = doc.first_node();
  while (root && root->type() != rapidxml_ns::node_element) root = root->next_sibling();
  if (!root || std::string(root->local_name(), root->local_name_size()) != "svg")
    throw SvgError(name + ": not an SVG file: its first element is " +
                   (root ? "<" + std::string(root->name(), root->name_size()) + ">" : std::string("missing")));
  check_node(root, name);
  apply_class_rules(doc, const_cast<rapidxml_ns::xml_node<>*>(root));
  expand_uses(doc, const_cast<rapidxml_ns::xml_node<>*>(root), name);
  const int kept = kept_out_of_sight(root->first_node(), false);

  SvgDrawing out;
  out.source = name;
  Context context(out);
  try {
    svgpp::document_traversal<svgpp::processed_elements<processed_elements_t>,
                              svgpp::processed_attributes<processed_attributes_t>,
                              svgpp::viewport_policy<svgpp::policy::viewport::as_transform>,
                              svgpp::path_policy<svgpp::policy::path::minimal>,
                              svgpp::error_policy<PassUnknown<Context>>>::load_document(root, context);
  } catch (const std::exception& e) {
    throw SvgError(name + ": cannot be read: " + e.what());
  }
  // drop subpaths with nothing drawn
  out.paths.erase(std::remove_if(out.paths.begin(), out.paths.end(), [](const SvgPath& p) { return p.cubics.empty(); }),
                  out.paths.end());
  if (out.paths.empty() && context.hidden() + kept > 0) {
    const int n = context.hidden() + kept;
    throw SvgError(name + ": nothing in it shows: its " + std::to_string(n) + (n == 1 ? " shape is" : " shapes are") +
                   " invisible (stroke and fill none, hidden, transparent, or kept in <defs> and no <use> shows it)");
  }
  if (out.paths.empty()) throw SvgError(name + ": no drawable path (paths, lines, polylines, polygons, rects, circles, ellipses)");
  bool any = false;
  for (const SvgPath& p : out.paths) {
    grow(out.bounds, any, p.start);
    for (const auto& c : p.cubics)
      for (const Point2& q : c) grow(out.bounds, any, q);
  }
  for (const SvgPath& p : out.paths)
    for (const auto& c : p.cubics)
      for (const Point2& q : c)
        if (!std::isfinite(q.x) || !std::isfinite(q.y)) throw SvgError(name + ": a coordinate is not a finite number");
  return out;
}

std::vector<Stroke> flatten_svg(const SvgDrawing& svg, double tolerance) {
  if (!(tolerance > 0)) throw std::invalid_argument("the chord tolerance must be > 0");
  std::vector<Stroke> out;
  for (const SvgPath& p : svg.paths) {
    Stroke s{p.start};
    Point2 at = p.start;
    for (const auto& c : p.cubics) {
      flatten_cubic(at, c[0], c[1], c[2], tolerance, s);
      at = c[2];
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace articula::host
