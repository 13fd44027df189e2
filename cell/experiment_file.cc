#include "cell/experiment_file.h"

#include "twin/base/json_field.h"

namespace cell {

Experiment read_experiment(const std::string& path) {
  const nlohmann::json doc = twin::JsonField::parse_file(path);
  const twin::JsonField root(doc, path);
  root.only_keys({"settle_s", "window_s", "states"});
  Experiment e;
  double settle_s = 6.0;
  if (auto v = root.optional("settle_s")) settle_s = v->non_negative("s");
  if (auto v = root.optional("window_s")) e.window_s = v->positive("s");
  const twin::JsonField states = root["states"];
  if (states.array_size() == 0) states.fail("must list at least one state");
  for (std::size_t i = 0; i < states.array_size(); ++i) {
    const twin::JsonField s = states[i];
    s.only_keys({"name", "actions", "settle_s"});
    ExperimentState state;
    state.name = s["name"].string();
    state.settle_s = settle_s;
    if (auto v = s.optional("settle_s")) state.settle_s = v->non_negative("s");
    if (auto actions = s.optional("actions")) {
      for (std::size_t k = 0; k < actions->array_size(); ++k) {
        const twin::JsonField a = (*actions)[k];
        ExperimentAction action;
        if (a.has("release")) {
          a.only_keys({"release"});
          action.gripper = a["release"].string();
        } else if (a.has("move")) {
          a.only_keys({"move", "to_m"});
          action.kind = ExperimentAction::Kind::kMove;
          action.gripper = a["move"].string();
          action.to_m = a["to_m"].vec3("m");
        } else {
          a.fail("must be {\"release\": GRIPPER} or {\"move\": GRIPPER, \"to_m\": [x, y, z]}");
        }
        state.actions.push_back(action);
      }
    }
    e.states.push_back(std::move(state));
  }
  return e;
}

}  // namespace cell
