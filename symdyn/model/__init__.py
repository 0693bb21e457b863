"""What a robot is: reading robot files and scenes into immutable descriptions.

Holds the robot file loader (:mod:`.robot`), scenes (:mod:`.scene`), the safe expression parser
(:mod:`.expr`), link geometry (:mod:`.geometry`), the names of the producible functions
(:mod:`.outputs`), the user-facing errors (:mod:`.errors`) and file access (:mod:`.files`).
Imports nothing from the other folders: everything after it builds on it.
"""
