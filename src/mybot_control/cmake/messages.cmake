# Services of mybot_control (included from CMakeLists.txt before generate_messages()).
add_service_files(FILES SetPose.srv)
