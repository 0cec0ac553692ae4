// A static scene from glTF 2.0 files (tinygltf): meshes in GL buffers, metallic-roughness
// materials, the node hierarchy flattened into draws with world matrices.
//
//   host::Scene scene;
//   scene.load("assets/terrain.gltf");               // adds the file's default scene
//   scene.load("assets/buildings.gltf");
//   const host::SceneNode* keep = scene.findNode("keep_far");   // world matrix and bounds
//
// What is read: triangles (indexed or not), POSITION, NORMAL (required: the renderer shades
// with them), COLOR_0 (optional, multiplies the base colour as glTF says), the material's
// baseColorFactor, metallicFactor and roughnessFactor, and node TRS or matrices. A file that
// needs anything else to look right (textures, sparse accessors, skins, morph targets, points
// or lines) is refused with a one-line error naming the file and the feature, rather than drawn
// wrongly. Lengths are the file's (glTF: metres), axes Y-up. Needs a current GL 4.5 context;
// errors are std::runtime_error.
#pragma once
#include <welkin_host/gl.hpp>

#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace host {

struct Bounds {
    glm::vec3 min{1e30f};
    glm::vec3 max{-1e30f};
    void add(const glm::vec3& p) { min = glm::min(min, p), max = glm::max(max, p); }
    bool empty() const { return min.x > max.x; }
};

struct Material {
    std::string name;
    glm::vec4 baseColor{1.0f};  ///< linear, multiplied by COLOR_0
    float metallic = 1.0f;      ///< glTF's defaults
    float roughness = 1.0f;
};

/// A named node of a loaded file: its world matrix and the world bounds of its own mesh.
struct SceneNode {
    std::string name;
    glm::mat4 world{1.0f};
    Bounds worldBounds;  ///< empty for a node without a mesh
};

class Scene {
public:
    Scene() = default;
    Scene(Scene&&) noexcept = default;
    Scene& operator=(Scene&&) noexcept = default;

    /// Loads a .gltf (with its .bin) or .glb and adds its default scene (or scene 0), placed by
    /// `transform`. Throws std::runtime_error("<path>: ...") on any error.
    void load(const std::string& path, const glm::mat4& transform = glm::mat4(1.0f));

    const std::vector<SceneNode>& nodes() const { return nodes_; }
    /// The first node with this name, or nullptr.
    const SceneNode* findNode(std::string_view name) const;
    Bounds bounds() const;
    size_t triangleCount() const;

    // For the renderer.
    struct Primitive {
        GlName vao, vbo, ebo;
        int indexCount = 0;
        int material = 0;
        Bounds localBounds;
    };
    struct Draw {
        int primitive = 0;
        glm::mat4 world{1.0f};
    };
    const std::vector<Primitive>& primitives() const { return primitives_; }
    const std::vector<Material>& materials() const { return materials_; }
    const std::vector<Draw>& draws() const { return draws_; }

private:
    std::vector<Primitive> primitives_;
    std::vector<Material> materials_;
    std::vector<Draw> draws_;
    std::vector<SceneNode> nodes_;
};

}  // namespace host
