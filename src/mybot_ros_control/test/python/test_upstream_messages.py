"""The message packages that stand in for upstream's (control_msgs, controller_manager_msgs,
gazebo_msgs, four_wheel_steering_msgs: Debian 12 packages none of them) define every type with upstream's name and MD5 sum,
so MoveIt's trajectory and gripper clients, ros_control tools and scripts written for Gazebo
connect to gazebo_lite as to Gazebo. The sums are the published ones of the Noetic packages, as
their generated code in other languages records them (checked one by one), not computed here."""
import importlib

import pytest

PUBLISHED = {
    "control_msgs": {
        "FollowJointTrajectoryAction": "bc4f9b743838566551c0390c65f1a248",
        "FollowJointTrajectoryActionFeedback": "d8920dc4eae9fc107e00999cce4be641",
        "FollowJointTrajectoryActionGoal": "cff5c1d533bf2f82dd0138d57f4304bb",
        "FollowJointTrajectoryActionResult": "c4fb3b000dc9da4fd99699380efcc5d9",
        "FollowJointTrajectoryFeedback": "10817c60c2486ef6b33e97dcd87f4474",
        "FollowJointTrajectoryGoal": "69636787b6ecbde4d61d711979bc7ecb",
        "FollowJointTrajectoryResult": "493383b18409bfb604b4e26c676401d2",
        "GripperCommand": "680acaff79486f017132a7f198d40f08",
        "GripperCommandAction": "950b2a6ebe831f5d4f4ceaba3d8be01e",
        "GripperCommandActionFeedback": "653dff30c045f5e6ff3feb3409f4558d",
        "GripperCommandActionGoal": "aa581f648a35ed681db2ec0bf7a82bea",
        "GripperCommandActionResult": "143702cb2df0f163c5283cedc5efc6b6",
        "GripperCommandFeedback": "e4cbff56d3562bcf113da5a5adeef91f",
        "GripperCommandGoal": "86fd82f4ddc48a4cb6856cfa69217e43",
        "GripperCommandResult": "e4cbff56d3562bcf113da5a5adeef91f",
        "JointControllerState": "987ad85e4756f3aef7f1e5e7fe0595d1",
        "JointTolerance": "f544fe9c16cf04547e135dd6063ff5be",
        "JointTrajectoryControllerState": "10817c60c2486ef6b33e97dcd87f4474",
        "QueryTrajectoryState": "ec93cdecbd8062d761aa52b7c90cd44b",
    },
    "controller_manager_msgs": {
        "ControllerState": "aeb6b261d97793ab74099a3740245272",
        "HardwareInterfaceResources": "f25b55cbf1d1f76e82e5ec9e83f76258",
        "ListControllerTypes": "c1d4cd11aefa9f97ba4aeb5b33987f4e",
        "ListControllers": "1341feb2e63fa791f855565d0da950d8",
        "LoadController": "647e5c54b8d6468952d8d31f1efe96c0",
        "ReloadControllerLibraries": "40e8c411fd1797d2e2c486018f846040",
        "SwitchController": "b29a7abc673b2c54c14b54e50f8d06a5",
        "UnloadController": "647e5c54b8d6468952d8d31f1efe96c0",
    },
    "four_wheel_steering_msgs": {
        "FourWheelSteering": "04dd0f55e1f168668af1e2587a7cdd2a",
        "FourWheelSteeringStamped": "9226582df815bc6df9e3206bc05923af",
    },
    "gazebo_msgs": {
        "ApplyBodyWrench": "585b9f9618aa0581b207e2f2d90866bc",
        "ApplyJointEffort": "c0039811b8cc919490b3cff748cdf46b",
        "BodyRequest": "5eade9afe7f232d78005bd0cafeab755",
        "ContactState": "48c0ffb054b8c444f870cecea1ee50d9",
        "ContactsState": "acbcb1601a8e525bf72509f18e6f668d",
        "DeleteModel": "9ce56b4e9e54616de25d796dc972a262",
        "GetJointProperties": "7b30be900f50aa21efec4a0ec92d91c9",
        "GetLinkProperties": "0e06a70386d0ee3fb880c02f23fcd821",
        "GetLinkState": "09d6c98cce97b35f7ab9bd70300657ab",
        "GetModelProperties": "5717f7bd34ed990fa80e28b3015027a3",
        "GetModelState": "4c515e936d3319c9610c559c60bfc3d4",
        "GetPhysicsProperties": "575a5e74786981b7df2e3afc567693a6",
        "GetWorldProperties": "36bb0f2eccf4d8be971410c22818ba3f",
        "JointRequest": "0be1351618e1dc030eb7959d9a4902de",
        "LinkState": "0818ebbf28ce3a08d48ab1eaa7309ebe",
        "LinkStates": "48c080191eb15c41858319b4d8a609c2",
        "ModelState": "9330fd35f2fcd82d457e54bd54e10593",
        "ModelStates": "48c080191eb15c41858319b4d8a609c2",
        "ODEJointProperties": "1b744c32a920af979f53afe2f9c3511f",
        "ODEPhysics": "667d56ddbd547918c32d1934503dc335",
        "PerformanceMetrics": "884f71fd5037b886ec5e126b83c4425a",
        "SensorPerformanceMetric": "01762ded18cfe9ebc7c8222667c99547",
        "SetJointProperties": "15a76e921b1410c698d82782ea5fa370",
        "SetLinkProperties": "d534ce1b36ee99de0ffa806c3a6348f0",
        "SetLinkState": "8a5146eb66ae4d26b0860b08f3f271be",
        "SetModelConfiguration": "10e3139d3b669c40afc057d38956fff7",
        "SetModelState": "5b3ab0281d4f5445def017e3a2e4a07b",
        "SetPhysicsProperties": "97e2057080558ce4730434b5fae75c91",
        "SpawnModel": "9ed9c82c96abe1a00c3e8cdaeee24413",
    },
}


def defined_types(package):
    """{name: class} of every message and service the package's Python module defines (the
    services' Request/Response halves are part of their service)."""
    out = {}
    for kind in ("msg", "srv"):
        try:
            module = importlib.import_module(package + "." + kind)
        except ModuleNotFoundError:
            continue
        for name in dir(module):
            cls = getattr(module, name)
            halves = [name[: -len(half)] for half in ("Request", "Response") if name.endswith(half)]
            if hasattr(cls, "_md5sum") and not any(hasattr(module, service) for service in halves):
                out[name] = cls
    return out


@pytest.mark.parametrize("package", sorted(PUBLISHED))
def test_every_type_has_upstreams_name_and_md5(package):
    types = defined_types(package)
    # Every type defined is one whose published sum is known here: none of ours slipped in.
    assert sorted(types) == sorted(PUBLISHED[package])
    for name, cls in types.items():
        assert cls._type == package + "/" + name
        assert cls._md5sum == PUBLISHED[package][name], name


def test_controller_manager_replies_are_upstreams():
    # Upstream's replies carry `ok` alone; why a call failed is in the manager's log.
    from controller_manager_msgs.srv import LoadControllerResponse, SwitchControllerResponse

    assert LoadControllerResponse.__slots__ == ["ok"]
    assert SwitchControllerResponse.__slots__ == ["ok"]
