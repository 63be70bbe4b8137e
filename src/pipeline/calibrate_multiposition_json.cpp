#include "detail/matrix_json.hpp"
#include "cubecal/pipeline/calibrate_multiposition_json.hpp"

#include <string>

namespace cubecal::pipeline {

namespace mp = cubecal::multipos;

namespace {

nlohmann::json residuals_json(const mp::Residuals& r) {
  return {{"count", r.count}, {"cost", r.cost}, {"rms", r.rms}, {"max", r.max}};
}

mp::Residuals residuals_of(const nlohmann::json& j) {
  return {j.at("count").get<std::size_t>(), j.at("cost").get<double>(), j.at("rms").get<double>(),
          j.at("max").get<double>()};
}

nlohmann::json params_json(const std::vector<std::string>& names, const std::vector<double>& v,
                           const std::vector<double>& s, const std::vector<std::string>& units) {
  nlohmann::json a = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i)
    a.push_back({{"name", names[i]}, {"value", v[i]}, {"sigma", s[i]}, {"unit", i < units.size() ? units[i] : ""}});
  return a;
}

void params_of(const nlohmann::json& a, std::vector<std::string>& names, std::vector<double>& v,
               std::vector<double>& s) {
  for (const auto& p : a) {
    names.push_back(p.at("name").get<std::string>());
    v.push_back(p.at("value").get<double>());
    s.push_back(p.at("sigma").get<double>());
  }
}

nlohmann::json model_json(const mp::TriadCalibration& m) {
  return {
      {"T", m.misalignment()},
      {"K", m.scale},
      {"B", m.bias},
      {"TK", m.matrix()},
      {"misalignment",
       {{"yz", m.mis_yz}, {"zy", m.mis_zy}, {"zx", m.mis_zx}, {"xz", m.mis_xz}, {"xy", m.mis_xy}, {"yx", m.mis_yx}}}};
}

mp::TriadCalibration model_of(const nlohmann::json& j) {
  mp::TriadCalibration m;
  m.scale = j.at("K").get<Vec3>();
  m.bias = j.at("B").get<Vec3>();
  const auto& a = j.at("misalignment");
  m.mis_yz = a.at("yz").get<double>();
  m.mis_zy = a.at("zy").get<double>();
  m.mis_zx = a.at("zx").get<double>();
  m.mis_xz = a.at("xz").get<double>();
  m.mis_xy = a.at("xy").get<double>();
  m.mis_yx = a.at("yx").get<double>();
  return m;
}

nlohmann::json options_json(const mp::Options& o) {
  return {{"g", o.g},
          {"init_static_s", o.init_static_s},
          {"window", o.window},
          {"interval_samples", o.interval_samples},
          {"min_intervals", o.min_intervals},
          {"th_mult_min", o.th_mult_min},
          {"th_mult_max", o.th_mult_max},
          {"acc_use_means", o.acc_use_means},
          {"acc_bias_guess", o.acc_bias_guess},
          {"acc_scale_guess", o.acc_scale_guess},
          {"gyro_scale_guess", o.gyro_scale_guess},
          {"refine_gyro_bias", o.refine_gyro_bias},
          {"max_iterations", o.max_iterations}};
}

mp::Options options_of(const nlohmann::json& j) {
  mp::Options o;
  o.g = j.at("g").get<double>();
  o.init_static_s = j.at("init_static_s").get<double>();
  o.window = j.at("window").get<std::size_t>();
  o.interval_samples = j.at("interval_samples").get<std::size_t>();
  o.min_intervals = j.at("min_intervals").get<std::size_t>();
  o.th_mult_min = j.at("th_mult_min").get<int>();
  o.th_mult_max = j.at("th_mult_max").get<int>();
  o.acc_use_means = j.at("acc_use_means").get<bool>();
  o.acc_bias_guess = j.at("acc_bias_guess").get<Vec3>();
  o.acc_scale_guess = j.at("acc_scale_guess").get<double>();
  o.gyro_scale_guess = j.at("gyro_scale_guess").get<double>();
  o.refine_gyro_bias = j.at("refine_gyro_bias").get<bool>();
  o.max_iterations = j.at("max_iterations").get<std::size_t>();
  return o;
}

}  // namespace

nlohmann::json to_json(const MultipositionResult& r) {
  const mp::AccResult& a = r.accelerometer;
  const mp::Options& opt = r.options;
  nlohmann::json j;
  j["method"] = "multi-position calibration without a turntable (Tedaldi, Pretto & Menegatti 2014)";
  j["acc_file"] = r.acc_file;
  j["gyro_file"] = r.gyro_file ? nlohmann::json(*r.gyro_file) : nlohmann::json(nullptr);
  j["model"] = "X' = T K (X - B); T = [[1, -mis_yz, mis_zy], [mis_xz, 1, -mis_zx], [-mis_xy, mis_yx, 1]]";
  j["samples"] = r.samples;
  j["rate_hz"] = r.rate_hz;
  j["g"] = opt.g;
  j["init_static_s"] = opt.init_static_s;
  j["window"] = mp::normalised_window(opt.window);
  j["interval_samples"] = opt.interval_samples;
  j["min_intervals"] = opt.min_intervals;
  j["options"] = options_json(opt);
  j["th_mult"] = a.th_mult;
  j["threshold"] = a.threshold;
  j["init_variance_norm"] = a.init_variance_norm;
  j["static_intervals"] = a.intervals.size();
  nlohmann::json iv = nlohmann::json::array();
  for (std::size_t k = 0; k < a.intervals.size(); ++k) {
    const IndexRange& i = a.intervals[k];
    const auto [t0, t1] = k < r.interval_times.size() ? r.interval_times[k] : std::pair{0.0, 0.0};
    iv.push_back({{"begin", i.begin}, {"end", i.end}, {"t_begin", t0}, {"t_end", t1}});
  }
  j["intervals"] = iv;
  nlohmann::json trials = nlohmann::json::array();
  for (const mp::Trial& t : a.trials)
    trials.push_back({{"th_mult", t.th_mult},
                      {"threshold", t.threshold},
                      {"intervals", t.intervals},
                      {"fitted", t.fitted},
                      {"cost", t.fitted ? nlohmann::json(t.cost) : nlohmann::json(nullptr)}});
  j["trials"] = trials;
  nlohmann::json ja;
  ja["parameters"] = params_json(a.names, a.values, a.sigma, multiposition_acc_units());
  ja["covariance"] = {{"names", a.names}, {"matrix", detail::to_json(a.covariance)}};
  ja["model"] = model_json(a.model);
  ja["initial"] = model_json(a.initial);
  ja["init_samples"] = a.init_samples;
  ja["residual"] = "g - |T K (a - B)|";
  ja["before"] = residuals_json(a.before);
  ja["after"] = residuals_json(a.after);
  ja["sigma0"] = a.sigma0;
  ja["iterations"] = a.iterations;
  ja["converged"] = a.converged;
  j["accelerometer"] = ja;
  if (const auto& g = r.gyroscope) {
    nlohmann::json jg;
    jg["parameters"] = params_json(g->names, g->values, g->sigma, multiposition_gyro_units(g->names.size()));
    jg["sigma_fit"] = g->sigma_fit;
    jg["covariance"] = {{"names", g->names}, {"matrix", detail::to_json(g->covariance)}};
    jg["model"] = model_json(g->model);
    jg["initial"] = model_json(g->initial);
    jg["init_bias"] = g->init_bias;
    jg["init_bias_sigma"] = g->init_bias_sigma;
    jg["bias_sigma"] = g->bias_sigma;
    jg["init_samples"] = g->init_samples;
    jg["residual"] = "R^-1 u_{k-1} - u_k";
    jg["pairs"] = g->pairs;
    jg["before"] = residuals_json(g->before);
    jg["after"] = residuals_json(g->after);
    jg["angle_rms_before_deg"] = g->angle_rms_before_deg;
    jg["angle_rms_after_deg"] = g->angle_rms_after_deg;
    jg["angle_max_after_deg"] = g->angle_max_after_deg;
    jg["sigma0"] = g->sigma0;
    jg["iterations"] = g->iterations;
    jg["converged"] = g->converged;
    j["gyroscope"] = jg;
  } else {
    j["gyroscope"] = nullptr;
  }
  return j;
}

MultipositionResult multiposition_result_from_json(const nlohmann::json& j) {
  MultipositionResult r;
  r.acc_file = j.at("acc_file").get<std::string>();
  if (!j.at("gyro_file").is_null()) r.gyro_file = j["gyro_file"].get<std::string>();
  r.samples = j.at("samples").get<std::size_t>();
  r.rate_hz = j.at("rate_hz").get<double>();
  r.options = options_of(j.at("options"));
  mp::AccResult& a = r.accelerometer;
  a.th_mult = j.at("th_mult").get<int>();
  a.threshold = j.at("threshold").get<double>();
  a.init_variance_norm = j.at("init_variance_norm").get<double>();
  for (const auto& i : j.at("intervals")) {
    a.intervals.push_back({i.at("begin").get<std::size_t>(), i.at("end").get<std::size_t>()});
    r.interval_times.emplace_back(i.at("t_begin").get<double>(), i.at("t_end").get<double>());
  }
  for (const auto& t : j.at("trials"))
    a.trials.push_back({t.at("th_mult").get<int>(), t.at("threshold").get<double>(),
                        t.at("intervals").get<std::size_t>(), t.at("fitted").get<bool>(),
                        t.at("cost").is_null() ? 0.0 : t["cost"].get<double>()});
  const auto& ja = j.at("accelerometer");
  params_of(ja.at("parameters"), a.names, a.values, a.sigma);
  a.covariance = detail::matrix_from_json(ja.at("covariance").at("matrix"));
  a.model = model_of(ja.at("model"));
  a.initial = model_of(ja.at("initial"));
  a.init_samples = ja.at("init_samples").get<std::size_t>();
  a.before = residuals_of(ja.at("before"));
  a.after = residuals_of(ja.at("after"));
  a.sigma0 = ja.at("sigma0").get<double>();
  a.iterations = ja.at("iterations").get<std::size_t>();
  a.converged = ja.at("converged").get<bool>();
  if (j.at("gyroscope").is_null()) return r;
  const auto& jg = j["gyroscope"];
  mp::GyroResult g;
  params_of(jg.at("parameters"), g.names, g.values, g.sigma);
  g.sigma_fit = jg.at("sigma_fit").get<std::vector<double>>();
  g.covariance = detail::matrix_from_json(jg.at("covariance").at("matrix"));
  g.model = model_of(jg.at("model"));
  g.initial = model_of(jg.at("initial"));
  g.init_bias = jg.at("init_bias").get<Vec3>();
  g.init_bias_sigma = jg.at("init_bias_sigma").get<Vec3>();
  g.bias_sigma = jg.at("bias_sigma").get<Vec3>();
  g.init_samples = jg.at("init_samples").get<std::size_t>();
  g.pairs = jg.at("pairs").get<std::size_t>();
  g.before = residuals_of(jg.at("before"));
  g.after = residuals_of(jg.at("after"));
  g.angle_rms_before_deg = jg.at("angle_rms_before_deg").get<double>();
  g.angle_rms_after_deg = jg.at("angle_rms_after_deg").get<double>();
  g.angle_max_after_deg = jg.at("angle_max_after_deg").get<double>();
  g.sigma0 = jg.at("sigma0").get<double>();
  g.iterations = jg.at("iterations").get<std::size_t>();
  g.converged = jg.at("converged").get<bool>();
  r.gyroscope = std::move(g);
  return r;
}

}  // namespace cubecal::pipeline
