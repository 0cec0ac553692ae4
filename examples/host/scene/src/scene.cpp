#include <welkin_host/scene.hpp>

#include <epoxy/gl.h>
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cstring>
#include <stdexcept>

namespace host {

namespace {

// One interleaved vertex: position, normal, colour (RGBA, linear).
struct Vertex {
    float p[3];
    float n[3];
    float c[4];
};

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw std::runtime_error(path + ": " + what); }

// Reads component `k` of element `i` of an accessor as float (normalised integers to [0, 1]).
class AccessorReader {
public:
    AccessorReader(const tinygltf::Model& m, int index, const std::string& path, const char* what) {
        if (index < 0 || size_t(index) >= m.accessors.size()) fail(path, std::string(what) + ": no accessor");
        const auto& a = m.accessors[size_t(index)];
        if (a.sparse.isSparse) fail(path, std::string(what) + ": sparse accessors are not supported");
        if (a.bufferView < 0) fail(path, std::string(what) + ": accessor without a buffer view");
        const auto& v = m.bufferViews[size_t(a.bufferView)];
        const auto& b = m.buffers[size_t(v.buffer)];
        type_ = a.componentType;
        normalized_ = a.normalized;
        count_ = a.count;
        components_ = tinygltf::GetNumComponentsInType(uint32_t(a.type));
        const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
        if (components_ <= 0 || csize <= 0) fail(path, std::string(what) + ": bad accessor type");
        stride_ = v.byteStride ? v.byteStride : size_t(components_ * csize);
        const size_t begin = v.byteOffset + a.byteOffset;
        const size_t need = count_ ? begin + stride_ * (count_ - 1) + size_t(components_ * csize) : begin;
        if (need > b.data.size() || a.byteOffset + (count_ ? stride_ * (count_ - 1) + size_t(components_ * csize) : 0) > v.byteLength)
            fail(path, std::string(what) + ": accessor runs past its buffer");
        data_ = b.data.data() + begin;
    }
    size_t count() const { return count_; }
    int components() const { return components_; }
    float get(size_t i, int k) const {
        const unsigned char* p = data_ + i * stride_;
        switch (type_) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p + 4 * k, 4); return f; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { float f = p[k]; return normalized_ ? f / 255.0f : f; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p + 2 * k, 2); return normalized_ ? u / 65535.0f : float(u); }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p + 4 * k, 4); return float(u); }
        default: return 0.0f;
        }
    }
    uint32_t index(size_t i) const {
        const unsigned char* p = data_ + i * stride_;
        switch (type_) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); return u; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); return u; }
        default: return 0;
        }
    }
    int type() const { return type_; }

private:
    const unsigned char* data_ = nullptr;
    size_t stride_ = 0, count_ = 0;
    int components_ = 0, type_ = 0;
    bool normalized_ = false;
};

glm::mat4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        glm::mat4 m;
        for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = float(n.matrix[size_t(i)]);  // column-major, as glTF
        return m;
    }
    glm::mat4 m(1.0f);
    if (n.translation.size() == 3) m[3] = glm::vec4(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]), 1.0f);
    if (n.rotation.size() == 4)
        m = m * glm::mat4_cast(glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])));
    if (n.scale.size() == 3) m = m * glm::scale(glm::mat4(1.0f), glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    return m;
}

}  // namespace

void Scene::load(const std::string& path, const glm::mat4& transform) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    const bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) {
        auto nl = err.find('\n');
        fail(path, "cannot load glTF: " + (err.empty() ? std::string("unknown error") : err.substr(0, nl)));
    }
    if (!model.skins.empty()) fail(path, "skins are not supported");
    if (!model.textures.empty()) fail(path, "textures are not supported (materials use factors and COLOR_0)");

    const int materialBase = int(materials_.size());
    for (const auto& m : model.materials) {
        const auto& pbr = m.pbrMetallicRoughness;
        Material mat;
        mat.name = m.name;
        mat.baseColor = glm::vec4(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]),
                                  float(pbr.baseColorFactor[3]));
        mat.metallic = float(pbr.metallicFactor);
        mat.roughness = float(pbr.roughnessFactor);
        materials_.push_back(mat);
    }
    const int defaultMaterial = int(materials_.size());
    materials_.push_back(Material{.name = "default"});

    // Meshes -> GL primitives (one VAO, VBO, EBO each).
    std::vector<std::vector<int>> meshPrimitives(model.meshes.size());
    for (size_t mi = 0; mi < model.meshes.size(); ++mi) {
        for (const auto& p : model.meshes[mi].primitives) {
            const std::string what = "mesh '" + model.meshes[mi].name + "'";
            if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) fail(path, what + ": only triangles are supported");
            if (!p.targets.empty()) fail(path, what + ": morph targets are not supported");
            auto pos = p.attributes.find("POSITION");
            auto nor = p.attributes.find("NORMAL");
            if (pos == p.attributes.end()) fail(path, what + ": no POSITION");
            if (nor == p.attributes.end()) fail(path, what + ": no NORMAL (the renderer needs normals)");
            AccessorReader P(model, pos->second, path, "POSITION"), N(model, nor->second, path, "NORMAL");
            if (P.type() != TINYGLTF_COMPONENT_TYPE_FLOAT || P.components() != 3 || N.type() != TINYGLTF_COMPONENT_TYPE_FLOAT ||
                N.components() != 3 || N.count() != P.count())
                fail(path, what + ": POSITION and NORMAL must be float VEC3 of one count");
            std::vector<Vertex> vertices(P.count());
            Primitive prim;
            for (size_t i = 0; i < P.count(); ++i) {
                Vertex& v = vertices[i];
                for (int k = 0; k < 3; ++k) v.p[k] = P.get(i, k), v.n[k] = N.get(i, k);
                v.c[0] = v.c[1] = v.c[2] = v.c[3] = 1.0f;
                prim.localBounds.add(glm::vec3(v.p[0], v.p[1], v.p[2]));
            }
            if (auto col = p.attributes.find("COLOR_0"); col != p.attributes.end()) {
                AccessorReader C(model, col->second, path, "COLOR_0");
                if (C.count() != P.count() || C.components() < 3) fail(path, what + ": COLOR_0 must be VEC3 or VEC4 of POSITION's count");
                for (size_t i = 0; i < C.count(); ++i)
                    for (int k = 0; k < C.components(); ++k) vertices[i].c[k] = C.get(i, k);
            }
            std::vector<uint32_t> indices;
            if (p.indices >= 0) {
                AccessorReader I(model, p.indices, path, "indices");
                indices.resize(I.count());
                for (size_t i = 0; i < I.count(); ++i) {
                    indices[i] = I.index(i);
                    if (indices[i] >= P.count()) fail(path, what + ": index out of range");
                }
            } else {
                indices.resize(P.count());
                for (size_t i = 0; i < P.count(); ++i) indices[i] = uint32_t(i);
            }
            if (indices.size() % 3) fail(path, what + ": index count not a multiple of 3");
            prim.indexCount = int(indices.size());
            prim.material = p.material >= 0 ? materialBase + p.material : defaultMaterial;
            prim.vbo = GlName::buffer();
            prim.ebo = GlName::buffer();
            prim.vao = GlName::vertexArray();
            glNamedBufferStorage(prim.vbo.id(), GLsizeiptr(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
            glNamedBufferStorage(prim.ebo.id(), GLsizeiptr(indices.size() * sizeof(uint32_t)), indices.data(), 0);
            const GLuint vao = prim.vao.id();
            glVertexArrayVertexBuffer(vao, 0, prim.vbo.id(), 0, sizeof(Vertex));
            glVertexArrayElementBuffer(vao, prim.ebo.id());
            const GLuint offsets[3] = {offsetof(Vertex, p), offsetof(Vertex, n), offsetof(Vertex, c)};
            const GLint sizes[3] = {3, 3, 4};
            for (GLuint a = 0; a < 3; ++a) {
                glEnableVertexArrayAttrib(vao, a);
                glVertexArrayAttribFormat(vao, a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
                glVertexArrayAttribBinding(vao, a, 0);
            }
            meshPrimitives[mi].push_back(int(primitives_.size()));
            primitives_.push_back(std::move(prim));
        }
    }

    // Nodes: depth-first from the scene's roots.
    const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (model.scenes.empty()) fail(path, "no scene");
    std::vector<std::pair<int, glm::mat4>> stack;
    for (int root : model.scenes[size_t(sceneIndex)].nodes) stack.push_back({root, transform});
    size_t visited = 0;
    while (!stack.empty()) {
        auto [ni, parent] = stack.back();
        stack.pop_back();
        if (ni < 0 || size_t(ni) >= model.nodes.size() || ++visited > 100000) fail(path, "bad node hierarchy");
        const auto& n = model.nodes[size_t(ni)];
        const glm::mat4 world = parent * nodeMatrix(n);
        SceneNode info{.name = n.name, .world = world, .worldBounds = {}};
        if (n.mesh >= 0) {
            if (size_t(n.mesh) >= model.meshes.size()) fail(path, "node '" + n.name + "': bad mesh index");
            for (int pi : meshPrimitives[size_t(n.mesh)]) {
                draws_.push_back({pi, world});
                const Bounds& b = primitives_[size_t(pi)].localBounds;
                for (int c = 0; c < 8; ++c) {
                    glm::vec3 corner((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y, (c & 4) ? b.max.z : b.min.z);
                    info.worldBounds.add(glm::vec3(world * glm::vec4(corner, 1.0f)));
                }
            }
        }
        nodes_.push_back(info);
        for (auto it = n.children.rbegin(); it != n.children.rend(); ++it) stack.push_back({*it, world});
    }
}

const SceneNode* Scene::findNode(std::string_view name) const {
    for (const auto& n : nodes_)
        if (n.name == name) return &n;
    return nullptr;
}

Bounds Scene::bounds() const {
    Bounds b;
    for (const auto& n : nodes_)
        if (!n.worldBounds.empty()) b.add(n.worldBounds.min), b.add(n.worldBounds.max);
    return b;
}

size_t Scene::triangleCount() const {
    size_t t = 0;
    for (const auto& d : draws_) t += size_t(primitives_[size_t(d.primitive)].indexCount / 3);
    return t;
}

}  // namespace host
