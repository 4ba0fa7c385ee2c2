#include "model/scene_writer.hpp"

#include <nlohmann/json.hpp>

namespace lieflow {

namespace {

using OrderedJson = nlohmann::ordered_json;

OrderedJson vec(const Eigen::Vector3d& v) { return OrderedJson::array({v.x(), v.y(), v.z()}); }
OrderedJson quat(const Eigen::Quaterniond& q) { return OrderedJson::array({q.w(), q.x(), q.y(), q.z()}); }

OrderedJson inertia(const Eigen::Matrix3d& I) {
  if (I.isDiagonal(0.0)) return vec(I.diagonal());
  OrderedJson rows = OrderedJson::array();
  for (int r = 0; r < 3; ++r) rows.push_back(vec(I.row(r).transpose()));
  return rows;
}

OrderedJson timeFunction(const TimeFunction& f) {
  using K = TimeFunction::Kind;
  switch (f.kind) {
    case K::kConstant: return f.value;
    case K::kRamp: return OrderedJson{{"type", "ramp"}, {"initial", f.initial}, {"rate", f.rate}};
    case K::kSine:
      return OrderedJson{{"type", "sine"}, {"amplitude", f.amplitude}, {"frequency", f.frequency},
                  {"phase", f.phase}, {"offset", f.offset}};
    case K::kTable: {
      OrderedJson points = OrderedJson::array();
      for (const auto& p : f.points) points.push_back(OrderedJson::array({p.first, p.second}));
      return OrderedJson{{"type", "table"}, {"points", points}};
    }
  }
  return f.value;
}

/// spring/damper/moment/prescribed of one coordinate (suffix "", "1", "2").
void writeCoordinate(const CoordinateDescription& c, const std::string& suffix, bool sliding, OrderedJson* j) {
  if (c.stiffness != 0.0 || c.rest_angle != 0.0)
    (*j)["spring" + suffix] = OrderedJson{{"stiffness", c.stiffness}, {sliding ? "rest_position" : "rest_angle", c.rest_angle}};
  if (c.damping != 0.0) (*j)["damper" + suffix] = OrderedJson{{"damping", c.damping}};
  if (c.moment) (*j)[(sliding ? "force" : "moment") + suffix] = timeFunction(*c.moment);
  if (c.prescribed) (*j)["prescribed" + suffix] = timeFunction(*c.prescribed);
}

OrderedJson nodeAxes(const NodeAxesDescription& n) {
  OrderedJson a{{"r", vec(n.r)}, {"s", vec(n.s)}};
  if (n.has_t) a["t"] = vec(n.t);
  return a;
}

OrderedJson joint(const JointDescription& d) {
  OrderedJson j{{"name", d.name}, {"type", d.type}, {"main", d.main}, {"secondary", d.secondary}};
  if (d.isGear()) {
    j["ratio"] = d.ratio;
    j["carrier"] = d.carrier;
    if (d.type == "coupling") {
      j["axis_main"] = vec(d.axes_main.r);
      j["motion_main"] = d.slide_main ? "slide" : "turn";
      j["axis_secondary"] = vec(d.axes_secondary.r);
      j["motion_secondary"] = d.slide_secondary ? "slide" : "turn";
      if (!d.carrier_secondary.empty() && d.carrier_secondary != d.carrier) j["carrier_secondary"] = d.carrier_secondary;
      return j;
    }
    j["axes_main"] = nodeAxes(d.axes_main);
    j["axes_secondary"] = nodeAxes(d.axes_secondary);
    if (d.type == "differential") {
      j["tertiary"] = d.tertiary;
      j["axes_tertiary"] = nodeAxes(d.axes_tertiary);
    }
    return j;
  }
  j["anchor_main"] = vec(d.anchor_main);
  j["anchor_secondary"] = vec(d.anchor_secondary);
  if (d.type == "revolute") {
    j["axis_main"] = vec(d.axis_main);
    if (d.has_axis_secondary) j["axis_secondary"] = vec(d.axis_secondary);
    if (d.initial_angles[0] != 0.0) j["initial_angle"] = d.initial_angles[0];
    writeCoordinate(d.coordinates[0], "", false, &j);
  } else if (d.type == "gimbal") {
    j["axis1_main"] = vec(d.axis_main);
    j["axis2_main"] = vec(d.axis2_main);
    j["axis3_main"] = vec(d.axis3_main);
    if (d.initial_angles != std::array<double, 3>{{0.0, 0.0, 0.0}})
      j["initial_angles"] = OrderedJson::array({d.initial_angles[0], d.initial_angles[1], d.initial_angles[2]});
    for (int i = 0; i < 3; ++i) writeCoordinate(d.coordinates[i], std::to_string(i + 1), false, &j);
  } else if (d.type == "prismatic") {
    j["axis_main"] = vec(d.axis_main);
    writeCoordinate(d.coordinates[0], "", true, &j);
  } else if (d.type == "universal") {
    j["axis1_main"] = vec(d.axis_main);
    j["axis2_secondary"] = vec(d.axis_secondary);
    if (d.offset) j["offset"] = true;
    if (d.initial_angles[0] != 0.0 || d.initial_angles[1] != 0.0)
      j["initial_angles"] = OrderedJson::array({d.initial_angles[0], d.initial_angles[1]});
    writeCoordinate(d.coordinates[0], "1", false, &j);
    writeCoordinate(d.coordinates[1], "2", false, &j);
  }
  return j;
}

}  // namespace

std::string sceneToJson(const SceneDescription& scene) {
  OrderedJson out;
  out["name"] = scene.name;
  if (!scene.description.empty()) out["description"] = scene.description;
  out["gravity"] = vec(scene.gravity);
  OrderedJson bodies = OrderedJson::array();
  for (const BodyDescription& b : scene.bodies) {
    OrderedJson j{{"name", b.name}, {"mass", b.mass}, {"inertia", inertia(b.inertia)}};
    if (b.rotation_only) j["rotation_only"] = true;
    j["orientation"] = quat(b.orientation);
    j["position"] = vec(b.position);
    j["angular_velocity"] = vec(b.angular_velocity);
    if (!b.rotation_only) j["velocity"] = vec(b.velocity);
    if (b.sensor != Eigen::Vector3d::Zero()) j["sensor"] = vec(b.sensor);
    if (b.spring_stiffness > 0.0)
      j["torsional_spring"] = OrderedJson{{"stiffness", b.spring_stiffness}, {"rest_orientation", quat(b.spring_rest)}};
    bodies.push_back(j);
  }
  out["bodies"] = bodies;
  OrderedJson joints = OrderedJson::array();
  for (const JointDescription& d : scene.joints) joints.push_back(joint(d));
  out["joints"] = joints;
  if (scene.has_integrator) {
    OrderedJson integrator{{"name", scene.integrator.name}, {"dt", scene.integrator.dt}};
    for (const auto& [key, value] : scene.integrator.options) integrator[key] = value;
    out["integrator"] = integrator;
  }
  if (scene.has_t_end) out["t_end"] = scene.t_end;
  return out.dump(2, ' ', false, OrderedJson::error_handler_t::replace) + "\n";
}

}  // namespace lieflow
