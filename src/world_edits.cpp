// Edits of a World's body list (world.hpp, "edits"): the Scene's edit plus the per-body input timelines
// and the waiting commands, which name bodies by index.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "rigid_body_sim/world.hpp"

namespace rigid_body {

CommandReply World::addBody(const BodyDefinition& body, const std::optional<CollisionShape>& shape,
                            std::size_t* index) {
  std::size_t added = 0;
  try {
    added = scene_.addBody(body, shape);
  } catch (const std::invalid_argument& error) {
    return {false, error.what()};
  }
  inputs_.emplace_back();
  if (index) *index = added;
  return {true, "body " + std::to_string(added) + " added at step " + std::to_string(clock_)};
}

CommandReply World::removeBody(std::size_t body) {
  try {
    scene_.removeBody(body);
  } catch (const std::invalid_argument& error) {
    return {false, error.what()};
  }
  inputs_.erase(inputs_.begin() + static_cast<std::ptrdiff_t>(body));
  scheduled_.erase(std::remove(scheduled_.begin(), scheduled_.end(), body), scheduled_.end());
  for (std::size_t& listed : scheduled_) listed -= listed > body ? 1 : 0;
  // The commands that name one body (the scene-wide ones leave their body index unread).
  const auto ofBody = [](const Command& command) {
    return command.kind == CommandKind::kTopicWrench || command.kind == CommandKind::kTimedWrench ||
           command.kind == CommandKind::kSetState || command.kind == CommandKind::kSetForces;
  };
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                [&](const Command& command) { return ofBody(command) && command.body == body; }),
                 pending_.end());
  for (Command& command : pending_) {
    if (ofBody(command) && command.body > body) --command.body;
  }
  return {true, "body " + std::to_string(body) + " removed at step " + std::to_string(clock_)};
}

}  // namespace rigid_body
