#include "BulletPeer.h"

#include "BenchScenes.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <algorithm>
#include <limits>

namespace cc::bench {

// Members in construction order: the world refers to the dispatcher, broadphase, solver and
// configuration, so it must be destroyed first (reverse declaration order does that).
struct BulletPatch::World {
    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
    std::unique_ptr<btSoftBody> patch;

    ~World() {
        if (patch) world.removeSoftBody(patch.get());
    }
};

BulletPatch::BulletPatch(int vertices, int positionIterations) : mWorld(std::make_unique<World>()) {
    btSoftBodyWorldInfo& info = mWorld->world.getWorldInfo();
    info.m_gravity = btVector3(0, btScalar(kGravity), 0);
    info.m_sparsesdf.Initialize();

    // Same corners as patchPanel(): u along +x, v along +z; fixeds 4 + 8 pin corner01 and corner11,
    // the two corners of the v = max edge.
    const btScalar y = btScalar(kPatchHeight);
    mWorld->patch.reset(btSoftBodyHelpers::CreatePatch(
        info, btVector3(-0.5f, y, 0), btVector3(0.5f, y, 0), btVector3(-0.5f, y, 1),
        btVector3(0.5f, y, 1), vertices, vertices, 4 + 8, true));
    btSoftBody& patch = *mWorld->patch;
    patch.generateBendingConstraints(2);
    patch.setTotalMass(btScalar(kPatchMass));
    if (positionIterations > 0) patch.m_cfg.piterations = positionIterations;
    mWorld->world.addSoftBody(&patch);
}

BulletPatch::~BulletPatch() = default;

int BulletPatch::step() {
    // maxSubSteps = 0 selects Bullet's variable time step: exactly one internal step of kDt.
    return mWorld->world.stepSimulation(btScalar(kDt), 0);
}

int BulletPatch::vertexCount() const { return mWorld->patch->m_nodes.size(); }

double BulletPatch::maxEdgeStrain() const {
    double strain = -std::numeric_limits<double>::infinity();
    const btSoftBody::tLinkArray& links = mWorld->patch->m_links;
    for (int i = 0; i < links.size(); ++i) {
        const btSoftBody::Link& link = links[i];
        if (link.m_bbending) continue;
        const double length = (link.m_n[1]->m_x - link.m_n[0]->m_x).length();
        strain = std::max(strain, length / link.m_rl - 1.0);
    }
    return strain;
}

double BulletPatch::lowestY() const {
    double lowest = std::numeric_limits<double>::infinity();
    const btSoftBody::tNodeArray& nodes = mWorld->patch->m_nodes;
    for (int i = 0; i < nodes.size(); ++i) lowest = std::min(lowest, double(nodes[i].m_x.y()));
    return lowest;
}

std::string bulletDescription() {
    const int version = btGetVersion();
    return "Bullet " + std::to_string(version / 100) + "." + std::to_string(version % 100) +
           ", btScalar = " + (sizeof(btScalar) == sizeof(double) ? "double" : "float");
}

} // namespace cc::bench
